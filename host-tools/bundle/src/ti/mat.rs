//! The part of MATLAB's MAT-file format (level 5, as `save` writes it, compressed or not) that
//! TI's calibration results use: named variables holding numeric matrices (real or complex)
//! and 1×1 structs of them. Everything else (cells, strings, sparse, struct arrays) is read past
//! and kept as [`MatValue::Other`].
//!
//! Little-endian files only (every MATLAB since R14 on x86 writes them). Sizes come from the
//! file and are checked against what remains before anything is allocated; decompression is
//! bounded by [`MAX_INFLATED_BYTES`].

use crate::error::InputError;
use std::io::Read;
use std::path::Path;

/// Largest MAT file read, bytes.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// Largest decompressed variable, bytes.
pub const MAX_INFLATED_BYTES: u64 = 256 << 20;
/// Deepest struct nesting followed.
const MAX_DEPTH: usize = 8;

const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_INT16: u32 = 3;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_SINGLE: u32 = 7;
const MI_DOUBLE: u32 = 9;
const MI_INT64: u32 = 12;
const MI_UINT64: u32 = 13;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;

const MX_STRUCT: u8 = 2;
/// mxDOUBLE_CLASS … mxUINT64_CLASS.
const MX_NUMERIC: std::ops::RangeInclusive<u8> = 6..=15;

/// A variable's value.
#[derive(Clone, Debug, PartialEq)]
pub enum MatValue {
    /// A numeric array, column-major, as `f64`.
    Numeric {
        /// Dimensions (at least two).
        dims: Vec<usize>,
        /// Real parts.
        re: Vec<f64>,
        /// Imaginary parts, if complex.
        im: Option<Vec<f64>>,
    },
    /// A 1×1 struct: its fields in file order.
    Struct(Vec<(String, MatValue)>),
    /// Anything else.
    Other,
}

impl MatValue {
    /// Field `name` of a struct.
    pub fn field(&self, name: &str) -> Option<&MatValue> {
        match self {
            MatValue::Struct(fields) => fields.iter().find(|(n, _)| n == name).map(|(_, v)| v),
            _ => None,
        }
    }
}

/// Why a file is not a MAT file this reader can use (the caller names the file).
#[derive(Debug)]
struct Malformed(String);

fn bad<T>(what: impl Into<String>) -> Result<T, Malformed> {
    Err(Malformed(what.into()))
}

/// A cursor over a byte slice.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn u32(&mut self) -> Result<u32, Malformed> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], Malformed> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return bad(format!(
                "an element of {n} bytes at offset {} runs past the end ({} bytes)",
                self.at,
                self.bytes.len()
            ));
        };
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn done(&self) -> bool {
        self.at >= self.bytes.len()
    }

    /// One data element: its type and payload (small elements included), cursor past its
    /// padding.
    fn element(&mut self) -> Result<(u32, &'a [u8]), Malformed> {
        let tag = self.u32()?;
        if tag >> 16 != 0 {
            // Small data element: size in the upper half, data in the next 4 bytes.
            let (ty, n) = (tag & 0xFFFF, (tag >> 16) as usize);
            let data = self.take(4)?;
            if n > 4 {
                return bad(format!("a small element claims {n} bytes"));
            }
            return Ok((ty, &data[..n]));
        }
        let n = self.u32()? as usize;
        let data = self.take(n)?;
        if tag != MI_COMPRESSED {
            let pad = (8 - n % 8) % 8;
            // The last element of a file may omit its padding.
            let pad = pad.min(self.bytes.len() - self.at);
            self.take(pad)?;
        }
        Ok((tag, data))
    }
}

/// Numbers of an element of type `ty`, as `f64`.
fn numbers(ty: u32, data: &[u8]) -> Result<Vec<f64>, Malformed> {
    let width = match ty {
        MI_INT8 | MI_UINT8 => 1,
        MI_INT16 | MI_UINT16 => 2,
        MI_INT32 | MI_UINT32 | MI_SINGLE => 4,
        MI_DOUBLE | MI_INT64 | MI_UINT64 => 8,
        _ => return bad(format!("numeric data of element type {ty}")),
    };
    if !data.len().is_multiple_of(width) {
        return bad(format!("{} bytes of {width}-byte numbers", data.len()));
    }
    Ok(data
        .chunks_exact(width)
        .map(|b| {
            let a8 = |b: &[u8]| {
                let mut a = [0u8; 8];
                a.copy_from_slice(b);
                a
            };
            match ty {
                MI_INT8 => f64::from(b[0] as i8),
                MI_UINT8 => f64::from(b[0]),
                MI_INT16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
                MI_UINT16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
                MI_INT32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                MI_UINT32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                MI_SINGLE => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                MI_INT64 => i64::from_le_bytes(a8(b)) as f64,
                MI_UINT64 => u64::from_le_bytes(a8(b)) as f64,
                _ => f64::from_le_bytes(a8(b)),
            }
        })
        .collect())
}

fn ints(ty: u32, data: &[u8]) -> Result<Vec<i64>, Malformed> {
    numbers(ty, data).map(|v| v.into_iter().map(|x| x as i64).collect())
}

/// A miMATRIX element's payload: its name and value.
fn matrix(data: &[u8], depth: usize) -> Result<(String, MatValue), Malformed> {
    if depth > MAX_DEPTH {
        return bad("structs nested too deep");
    }
    if data.is_empty() {
        return Ok((String::new(), MatValue::Other));
    }
    let mut c = Cursor { bytes: data, at: 0 };
    let (ty, flags) = c.element()?;
    if ty != MI_UINT32 || flags.len() < 4 {
        return bad("a matrix without its array flags");
    }
    let class = flags[0];
    let complex = flags[1] & 0x08 != 0;
    let (ty, dims) = c.element()?;
    let dims: Vec<usize> = ints(ty, dims)?
        .into_iter()
        .map(|d| usize::try_from(d).map_err(|_| Malformed(format!("dimension {d}"))))
        .collect::<Result<_, _>>()?;
    let (_, name) = c.element()?;
    let name = String::from_utf8_lossy(name).into_owned();
    let count = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| Malformed("dimensions overflow".into()))?;
    let value = if MX_NUMERIC.contains(&class) {
        let (ty, re) = c.element()?;
        let re = numbers(ty, re)?;
        let im = if complex {
            let (ty, im) = c.element()?;
            Some(numbers(ty, im)?)
        } else {
            None
        };
        if re.len() != count || im.as_ref().is_some_and(|v| v.len() != count) {
            return bad(format!(
                "variable `{name}` has {} values for dimensions {dims:?}",
                re.len()
            ));
        }
        MatValue::Numeric { dims, re, im }
    } else if class == MX_STRUCT && count == 1 {
        let (ty, len) = c.element()?;
        let len = *ints(ty, len)?.first().unwrap_or(&0) as usize;
        let (_, names) = c.element()?;
        if len == 0 || names.len() % len != 0 {
            return bad(format!("struct `{name}` has malformed field names"));
        }
        let mut fields = Vec::new();
        for raw in names.chunks_exact(len) {
            let end = raw.iter().position(|&b| b == 0).unwrap_or(raw.len());
            let field = String::from_utf8_lossy(&raw[..end]).into_owned();
            let (ty, body) = c.element()?;
            if ty != MI_MATRIX {
                return bad(format!("field `{field}` of `{name}` is not a matrix"));
            }
            fields.push((field, matrix(body, depth + 1)?.1));
        }
        MatValue::Struct(fields)
    } else {
        MatValue::Other
    };
    Ok((name, value))
}

/// Every top-level variable of a MAT file's bytes.
fn variables(bytes: &[u8]) -> Result<Vec<(String, MatValue)>, Malformed> {
    if bytes.len() < 128 {
        return bad("shorter than the 128-byte MAT header");
    }
    if &bytes[126..128] != b"IM" {
        return bad(if &bytes[126..128] == b"MI" {
            "a big-endian MAT file; save it again on a little-endian machine".to_owned()
        } else {
            "no MAT-file version 5 header (save it with `save -v7` or `-v6`; v7.3 HDF5 files are not read)".to_owned()
        });
    }
    let mut c = Cursor {
        bytes: &bytes[128..],
        at: 0,
    };
    let mut out = Vec::new();
    while !c.done() {
        let (ty, data) = c.element()?;
        match ty {
            MI_MATRIX => out.push(matrix(data, 0)?),
            MI_COMPRESSED => {
                let mut inflated = Vec::new();
                flate2::read::ZlibDecoder::new(data)
                    .take(MAX_INFLATED_BYTES + 1)
                    .read_to_end(&mut inflated)
                    .map_err(|e| {
                        Malformed(format!("a compressed variable does not inflate ({e})"))
                    })?;
                if inflated.len() as u64 > MAX_INFLATED_BYTES {
                    return bad(format!(
                        "a compressed variable inflates past {MAX_INFLATED_BYTES} bytes"
                    ));
                }
                let mut inner = Cursor {
                    bytes: &inflated,
                    at: 0,
                };
                let (ty, data) = inner.element()?;
                if ty == MI_MATRIX {
                    out.push(matrix(data, 0)?);
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Reads every top-level variable of the MAT file at `path`.
///
/// # Errors
/// [`InputError`] naming the file when it cannot be read or is not a MAT v5 file.
pub fn read(path: &Path) -> Result<Vec<(String, MatValue)>, InputError> {
    parse(path, &crate::limits::read_bounded(path, MAX_FILE_BYTES)?)
}

/// [`read`] on the bytes of `path` already read.
///
/// # Errors
/// [`InputError`] naming `path` when the bytes are not a MAT v5 file.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Vec<(String, MatValue)>, InputError> {
    variables(bytes).map_err(|Malformed(m)| InputError::file(path, m))
}
