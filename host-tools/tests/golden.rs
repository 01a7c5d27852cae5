//! Proof that a restructuring changed no behaviour: every command of
//! `tests/data/golden/commands.txt` run with this build's `metamoran` must print, byte for byte,
//! what the commit before the restructuring printed (stored by `tests/data/golden/make.sh`).
//! Only the top-level keys of `volatile.txt` (timings, firmware section sizes) are left out, on
//! both sides alike.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/golden")
}

/// `volatile.txt`: per output file, the keys to leave out.
fn volatile(dir: &Path) -> BTreeMap<String, Vec<String>> {
    let mut keys: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for line in std::fs::read_to_string(dir.join("volatile.txt"))
        .unwrap()
        .lines()
    {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (file, key) = line.split_once('\t').expect("volatile.txt: FILE<TAB>KEY");
        keys.entry(file.to_owned())
            .or_default()
            .push(key.to_owned());
    }
    keys
}

/// `text` without the lines that hold one of `keys` (pretty JSON: one scalar key a line, or an
/// object whose lines run to the `}` at the key's indentation).
fn without(text: &str, keys: &[String]) -> String {
    let mut out = Vec::new();
    let mut skipping: Option<usize> = None;
    for l in text.lines() {
        let body = l.trim_start();
        let indent = l.len() - body.len();
        if let Some(at) = skipping {
            if indent == at && body.starts_with('}') {
                skipping = None;
            }
            continue;
        }
        if keys.iter().any(|k| body.starts_with(&format!("\"{k}\":"))) {
            if body.ends_with('{') {
                skipping = Some(indent);
            }
            continue;
        }
        out.push(l);
    }
    out.join("\n")
}

#[test]
fn outputs_are_identical_to_the_commit_before_the_restructuring() {
    let dir = golden_dir();
    let volatile = volatile(&dir);
    let work = tempfile::tempdir().unwrap();
    let folder = |name: &str| {
        let p = work.path().join(name);
        std::fs::create_dir_all(&p).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let (scenes, drives, tmp) = (folder("scenes"), folder("drives"), folder("tmp"));
    let mut compared = 0;
    for line in std::fs::read_to_string(dir.join("commands.txt"))
        .unwrap()
        .lines()
    {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (name, args) = line.split_once('\t').expect("commands.txt: NAME<TAB>ARGS");
        let args = args
            .replace("{scenes}", &scenes)
            .replace("{drives}", &drives)
            .replace("{tmp}", &tmp);
        let out = Command::new(env!("CARGO_BIN_EXE_metamoran"))
            .args(args.split_whitespace())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "metamoran {args}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        if name == "-" {
            continue;
        }
        let keys = volatile.get(name).map_or(&[][..], Vec::as_slice);
        let expected = std::fs::read_to_string(dir.join(name)).unwrap();
        let got = String::from_utf8(out.stdout).unwrap();
        assert!(
            !expected.trim().is_empty(),
            "{name}: the stored output is empty"
        );
        assert_eq!(
            without(&got, keys),
            without(&expected, keys),
            "metamoran {args}: output differs from tests/data/golden/{name}"
        );
        compared += 1;
    }
    assert!(compared >= 9, "only {compared} outputs compared");
}
