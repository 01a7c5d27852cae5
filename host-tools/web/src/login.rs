//! Operator logins: a users file of argon2id password hashes (PHC strings), sessions that
//! expire, and a per-address limit on login attempts.
//!
//! ```text
//! # users file: one `user:hash` per line (metamoran hash-password makes the hash)
//! alice:$argon2id$v=19$m=19456,t=2,p=1$…
//! ```

use crate::WebError;
use argon2::password_hash::rand_core::{OsRng, RngCore};
use argon2::password_hash::{PasswordHash, PasswordHasher, PasswordVerifier, SaltString};
use std::collections::{BTreeMap, HashMap};
use std::net::IpAddr;
use std::path::Path;
use std::time::{Duration, Instant};

/// Largest users file read, bytes.
pub const MAX_USERS_BYTES: u64 = 64 * 1024;

/// The operators who may log in, each with an argon2 hash of their password.
#[derive(Clone, Debug)]
pub struct Users {
    hashes: BTreeMap<String, String>,
    /// A hash of nothing anyone knows, checked for unknown users.
    dummy: String,
}

/// An argon2id hash (default parameters, random salt) of `password`, as a PHC string.
///
/// # Errors
/// [`WebError::Users`] if hashing fails.
pub fn hash_password(password: &str) -> Result<String, WebError> {
    let salt = SaltString::generate(&mut OsRng);
    argon2::Argon2::default()
        .hash_password(password.as_bytes(), &salt)
        .map(|h| h.to_string())
        .map_err(|e| WebError::Users {
            path: "password".into(),
            problem: format!("cannot hash ({e})"),
        })
}

impl Users {
    /// Reads a users file.
    ///
    /// # Errors
    /// [`WebError::Users`] naming the file and line that is unreadable or not `user:hash`.
    pub fn load(path: &Path) -> Result<Self, WebError> {
        let problem = |problem: String| WebError::Users {
            path: path.display().to_string(),
            problem,
        };
        let len = std::fs::metadata(path)
            .map_err(|e| problem(format!("cannot read ({e})")))?
            .len();
        if len > MAX_USERS_BYTES {
            return Err(problem(format!("{len} bytes; at most {MAX_USERS_BYTES}")));
        }
        let text =
            std::fs::read_to_string(path).map_err(|e| problem(format!("cannot read ({e})")))?;
        Self::parse(&text).map_err(problem)
    }

    /// Parses users-file text; the problem names the line.
    ///
    /// # Errors
    /// The line that is not `user:hash` with an argon2 PHC hash.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut users = BTreeMap::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let (user, hash) = line
                .split_once(':')
                .ok_or_else(|| format!("line {}: give user:hash", n + 1))?;
            if user.is_empty() || user.len() > 64 {
                return Err(format!(
                    "line {}: give a user name of 1–64 characters",
                    n + 1
                ));
            }
            let parsed = PasswordHash::new(hash).map_err(|e| {
                format!(
                    "line {} ({user}): not a PHC hash ({e}); make one with metamoran hash-password",
                    n + 1
                )
            })?;
            if !parsed.algorithm.as_str().starts_with("argon2") {
                return Err(format!("line {} ({user}): not an argon2 hash", n + 1));
            }
            if users.insert(user.to_owned(), hash.to_owned()).is_some() {
                return Err(format!("line {}: {user} is listed twice", n + 1));
            }
        }
        if users.is_empty() {
            return Err("no users: add a user:hash line".into());
        }
        let dummy = hash_password(&format!("{:?}", std::time::SystemTime::now()))
            .map_err(|e| e.to_string())?;
        Ok(Self {
            hashes: users,
            dummy,
        })
    }

    /// Whether `password` is `user`'s. Takes about as long for an unknown user (a dummy hash is
    /// checked), so the answer's time does not tell which users exist.
    pub fn verify(&self, user: &str, password: &str) -> bool {
        let known = self.hashes.get(user);
        let hash = known.unwrap_or(&self.dummy);
        let ok = PasswordHash::new(hash).is_ok_and(|h| {
            argon2::Argon2::default()
                .verify_password(password.as_bytes(), &h)
                .is_ok()
        });
        ok && known.is_some()
    }
}

/// Login attempts allowed per address in [`LOGIN_WINDOW`].
pub const LOGIN_ATTEMPTS: u32 = 5;
/// The window of [`LOGIN_ATTEMPTS`].
pub const LOGIN_WINDOW: Duration = Duration::from_secs(60);

/// Sessions and login attempts.
#[derive(Debug, Default)]
pub struct Sessions {
    /// Token → user and expiry.
    live: HashMap<String, (String, Instant)>,
    /// Address → attempts in the current window and its start.
    attempts: HashMap<IpAddr, (u32, Instant)>,
}

impl Sessions {
    /// Counts a login attempt from `ip`; whether it is within the limit.
    pub fn attempt(&mut self, ip: IpAddr, now: Instant) -> bool {
        let e = self.attempts.entry(ip).or_insert((0, now));
        if now.duration_since(e.1) > LOGIN_WINDOW {
            *e = (0, now);
        }
        e.0 += 1;
        e.0 <= LOGIN_ATTEMPTS
    }

    /// A new session for `user`, valid for `ttl`; its token (256 random bits, hex).
    pub fn open(&mut self, user: &str, ttl: Duration, now: Instant) -> String {
        let mut bytes = [0u8; 32];
        OsRng.fill_bytes(&mut bytes);
        let token: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        self.live.retain(|_, (_, until)| *until > now);
        self.live
            .insert(token.clone(), (user.to_owned(), now + ttl));
        token
    }

    /// The user of session `token`, if it is live.
    pub fn user(&self, token: &str, now: Instant) -> Option<&str> {
        self.live
            .get(token)
            .filter(|(_, until)| *until > now)
            .map(|(u, _)| u.as_str())
    }

    /// Ends session `token`.
    pub fn close(&mut self, token: &str) {
        self.live.remove(token);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hash_verifies_its_password_only() {
        let hash = hash_password("correct horse").unwrap();
        assert!(hash.starts_with("$argon2id$"), "{hash}");
        let users = Users::parse(&format!("# operators\nalice:{hash}\n")).unwrap();
        assert!(users.verify("alice", "correct horse"));
        assert!(!users.verify("alice", "correct horse "));
        assert!(!users.verify("bob", "correct horse"));
        for (text, says) in [
            ("alice", "line 1: give user:hash"),
            ("alice:plain", "line 1 (alice): not a PHC hash"),
            ("", "no users"),
        ] {
            let e = Users::parse(text).unwrap_err();
            assert!(e.contains(says), "{e}");
        }
        let twice = format!("a:{hash}\na:{hash}\n");
        assert!(
            Users::parse(&twice)
                .unwrap_err()
                .contains("line 2: a is listed twice")
        );
    }

    #[test]
    fn sessions_expire_and_logins_are_limited() {
        let mut s = Sessions::default();
        let t0 = Instant::now();
        let token = s.open("alice", Duration::from_secs(10), t0);
        assert_eq!(token.len(), 64);
        assert_eq!(s.user(&token, t0 + Duration::from_secs(9)), Some("alice"));
        assert_eq!(s.user(&token, t0 + Duration::from_secs(11)), None);
        assert_ne!(s.open("alice", Duration::from_secs(10), t0), token);
        let ip: IpAddr = [127, 0, 0, 1].into();
        assert!((0..LOGIN_ATTEMPTS).all(|_| s.attempt(ip, t0)));
        assert!(
            !s.attempt(ip, t0),
            "the sixth attempt in a minute is refused"
        );
        assert!(
            s.attempt([127, 0, 0, 2].into(), t0),
            "another address is not"
        );
        assert!(s.attempt(ip, t0 + LOGIN_WINDOW + Duration::from_secs(1)));
    }
}
