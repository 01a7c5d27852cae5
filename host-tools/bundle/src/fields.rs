//! Typed access to TOML tables that names the file and the dotted field on every error.

use crate::error::InputError;
use std::path::Path;
use toml::{Table, Value};

/// A view of one table of a TOML file.
pub struct Fields<'a> {
    path: &'a Path,
    table: &'a Table,
    prefix: String,
}

impl<'a> Fields<'a> {
    /// The top-level table of `path`.
    pub fn root(path: &'a Path, table: &'a Table) -> Self {
        Self {
            path,
            table,
            prefix: String::new(),
        }
    }

    /// The dotted name of `key` in this table.
    pub fn name(&self, key: &str) -> String {
        if self.prefix.is_empty() {
            key.to_owned()
        } else {
            format!("{}.{key}", self.prefix)
        }
    }

    /// An error about `key`.
    pub fn error(&self, key: &str, problem: impl Into<String>) -> InputError {
        InputError::field(self.path, self.name(key), problem)
    }

    /// Checks that every key of the table is one of `known`: a misspelt key (`tx_elevaton`)
    /// is an error with the nearest known key, never silently ignored.
    ///
    /// # Errors
    /// [`InputError`] naming the first unknown key.
    pub fn only(&self, known: &[&str]) -> Result<(), InputError> {
        let Some(key) = self.table.keys().find(|k| !known.contains(&k.as_str())) else {
            return Ok(());
        };
        let nearest = known
            .iter()
            .map(|k| (strsim::levenshtein(key, k), *k))
            .min()
            .filter(|&(d, k)| d <= 3.max(k.len() / 3));
        Err(self.error(
            key,
            match nearest {
                Some((_, k)) => format!("unknown key; did you mean `{}`?", self.name(k)),
                None => format!("unknown key; this table has {}", known.join(", ")),
            },
        ))
    }

    /// Whether `key` is present.
    pub fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    fn get(&self, key: &str, expected: &str) -> Result<&'a Value, InputError> {
        self.table
            .get(key)
            .ok_or_else(|| self.error(key, format!("missing; add it ({expected})")))
    }

    /// A sub-table.
    pub fn table(&self, key: &str) -> Result<Fields<'a>, InputError> {
        match self.get(key, "a table")? {
            Value::Table(t) => Ok(Fields {
                path: self.path,
                table: t,
                prefix: self.name(key),
            }),
            v => Err(self.error(key, format!("expected a table, found {}", v.type_str()))),
        }
    }

    /// A string.
    pub fn string(&self, key: &str) -> Result<&'a str, InputError> {
        match self.get(key, "a string")? {
            Value::String(s) => Ok(s),
            v => Err(self.error(key, format!("expected a string, found {}", v.type_str()))),
        }
    }

    /// A finite number (integer or float).
    pub fn f64(&self, key: &str) -> Result<f64, InputError> {
        let v = match self.get(key, "a number")? {
            Value::Float(f) => *f,
            Value::Integer(i) => *i as f64,
            v => return Err(self.error(key, format!("expected a number, found {}", v.type_str()))),
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(key, format!("{v} is not a finite number")))
        }
    }

    /// A positive finite number.
    pub fn positive(&self, key: &str) -> Result<f64, InputError> {
        let v = self.f64(key)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.error(key, format!("{v} must be greater than zero")))
        }
    }

    /// An integer in `min..=max`.
    pub fn integer(&self, key: &str, min: i64, max: i64) -> Result<i64, InputError> {
        match self.get(key, "an integer")? {
            Value::Integer(i) if (min..=max).contains(i) => Ok(*i),
            Value::Integer(i) => Err(self.error(key, format!("{i} is outside {min}..={max}"))),
            v => Err(self.error(key, format!("expected an integer, found {}", v.type_str()))),
        }
    }

    /// An array of numbers.
    pub fn f64_list(&self, key: &str) -> Result<Vec<f64>, InputError> {
        let Value::Array(items) = self.get(key, "an array of numbers")? else {
            return Err(self.error(key, "expected an array of numbers"));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                Value::Float(f) if f.is_finite() => Ok(*f),
                Value::Integer(n) => Ok(*n as f64),
                _ => Err(self.error(&format!("{key}[{i}]"), "expected a finite number")),
            })
            .collect()
    }

    /// An array of whole numbers in `min..=max` (integral floats such as `4.0` are accepted).
    pub fn int_list(&self, key: &str, min: i64, max: i64) -> Result<Vec<i64>, InputError> {
        self.f64_list(key)?
            .into_iter()
            .enumerate()
            .map(|(i, v)| {
                if v.fract() != 0.0 {
                    Err(self.error(
                        &format!("{key}[{i}]"),
                        format!("{v} must be a whole number"),
                    ))
                } else if !(min as f64..=max as f64).contains(&v) {
                    Err(self.error(
                        &format!("{key}[{i}]"),
                        format!("{v} is outside {min}..={max}"),
                    ))
                } else {
                    Ok(v as i64)
                }
            })
            .collect()
    }
}

/// Parses `text` (the contents of `path`) as a TOML table.
pub fn parse_toml(path: &Path, text: &str) -> Result<Table, InputError> {
    text.parse::<Table>().map_err(|e| InputError::Syntax {
        path: path.to_owned(),
        format: "TOML",
        message: e.to_string(),
    })
}
