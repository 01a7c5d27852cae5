//! Input errors: every one names the file and, where there is one, the field.

use std::path::{Path, PathBuf};

/// A problem with an input file. The message says which file, which field, and what to do.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file could not be read.
    #[error("{}: cannot read it ({source}); check the path and permissions", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not valid TOML or JSON.
    #[error("{}: not valid {format}: {message}", path.display())]
    Syntax {
        /// The file.
        path: PathBuf,
        /// "TOML" or "JSON".
        format: &'static str,
        /// The parser's message (with line and column).
        message: String,
    },
    /// A field is missing or has a bad value.
    #[error("{}: field `{field}`: {problem}", path.display())]
    Field {
        /// The file.
        path: PathBuf,
        /// Dotted path of the field, e.g. `radar.adc_samples` or `frames[2].objects[0].depth_m`.
        field: String,
        /// What is wrong and what is expected.
        problem: String,
    },
    /// A bundle file (or its folder) could not be written.
    #[error("{}: cannot write ({source}); check the folder exists and is writable", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A camera model could not be loaded or breaks its contract.
    #[error("{0}")]
    Model(String),
    /// A camera model was given to a build without ONNX support.
    #[error(
        "this metamoran was built without ONNX support; build it with `cargo build --release -p metamoran --features onnx` to use --segmenter or --depth-model"
    )]
    NoOnnx,
    /// The file as a whole is wrong (size, image format, …).
    #[error("{}: {problem}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong and what is expected.
        problem: String,
    },
}

impl InputError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_owned(),
            source,
        }
    }

    /// A bad field of `path`.
    pub fn field(path: &Path, field: impl Into<String>, problem: impl Into<String>) -> Self {
        Self::Field {
            path: path.to_owned(),
            field: field.into(),
            problem: problem.into(),
        }
    }

    /// `path` could not be written.
    pub fn write(path: &Path, source: std::io::Error) -> Self {
        Self::Write {
            path: path.to_owned(),
            source,
        }
    }

    /// A problem with the whole of `path`.
    pub fn file(path: &Path, problem: impl Into<String>) -> Self {
        Self::File {
            path: path.to_owned(),
            problem: problem.into(),
        }
    }
}

/// Reads a whole regular file of at most `limit` bytes, naming it on failure
/// ([`crate::limits`]).
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    crate::limits::read_bounded(path, limit)
}

/// Reads a whole UTF-8 regular file of at most `limit` bytes, naming it on failure.
pub fn read_text(path: &Path, limit: u64) -> Result<String, InputError> {
    let bytes = read(path, limit)?;
    String::from_utf8(bytes).map_err(|e| InputError::file(path, format!("not UTF-8 text ({e})")))
}

/// Reads and deserializes a JSON file of at most `limit` bytes; a type error names the path of
/// the failing field (e.g. `frames[0].objects[2].depth_m`).
pub fn read_json<T: serde::de::DeserializeOwned>(path: &Path, limit: u64) -> Result<T, InputError> {
    parse_json(path, &read(path, limit)?)
}

/// Deserializes JSON `bytes` (the contents of `path`); a type error names the failing field.
pub fn parse_json<T: serde::de::DeserializeOwned>(
    path: &Path,
    bytes: &[u8],
) -> Result<T, InputError> {
    let de = &mut serde_json::Deserializer::from_slice(bytes);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        let inner = e.into_inner();
        if inner.is_syntax() || inner.is_eof() {
            InputError::Syntax {
                path: path.to_owned(),
                format: "JSON",
                message: inner.to_string(),
            }
        } else {
            InputError::field(path, field, inner.to_string())
        }
    })
}
