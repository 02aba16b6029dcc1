//! NumPy `.npy` arrays of points: what `np.save("points.npy", xyz)` writes
//! for an (N, 3) array of `float32` or `float64`.
//!
//! The header is read as numpy writes it: the magic string, a format
//! version (1.0, 2.0 or 3.0), the header's length, and a Python dict literal
//! with `descr`, `fortran_order` and `shape`. Accepted: `descr` `<f4` or
//! `<f8` (little-endian floats; `|`/`=` byte orders on little-endian
//! machines), either order, shape `(N, 3)`. `float64` values are rounded to
//! the nearest `f32`, as the points of a text file are.
//!
//! Refused, each with a message that says what was found: another magic
//! string or version, a header that does not parse, another dtype
//! (integers, big-endian, objects), another shape, fewer or more data bytes
//! than the shape holds, and coordinates that are not finite or lie beyond
//! the query bound (naming the point's row).

use super::text::{syntax, truncated};
use crate::build::MAX_QUERY_COORDINATE;
use crate::error::LoadError;
use crate::math::Vec3;
use std::path::Path;

/// The first bytes of every `.npy` file.
const MAGIC: &[u8] = b"\x93NUMPY";

/// Parses the bytes of a `.npy` file holding an (N, 3) array of floats as
/// points (see the module documentation).
///
/// ```
/// // np.save of np.array([[1, 2, 3]], dtype="<f4"), header padded to 64 bytes.
/// let mut file = b"\x93NUMPY\x01\x00\x76\x00".to_vec();
/// let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 3), }";
/// file.extend(format!("{dict:<117}\n").bytes());
/// for v in [1f32, 2.0, 3.0] {
///     file.extend(v.to_le_bytes());
/// }
/// let points = proxima::io::parse_npy_points(&file, "p.npy".as_ref())?;
/// assert_eq!(points, [proxima::Vec3::new(1.0, 2.0, 3.0)]);
/// # Ok::<(), proxima::LoadError>(())
/// ```
pub fn parse_npy_points(bytes: &[u8], path: &Path) -> Result<Vec<Vec3>, LoadError> {
    let header = Header::parse(bytes, path)?;
    let data = &bytes[header.data_start..];
    let expected = header.rows as u128 * 3 * header.width as u128;
    if (data.len() as u128) < expected {
        return Err(truncated(
            path,
            None,
            format!(
                "the .npy header's shape ({}, 3) needs {expected} data bytes, the file holds {}",
                header.rows,
                data.len()
            ),
        ));
    }
    if data.len() as u128 > expected {
        return Err(syntax(
            path,
            None,
            format!(
                "{} bytes after the ({}, 3) array the .npy header announces",
                data.len() as u128 - expected,
                header.rows
            ),
        ));
    }
    let value = |k: usize| -> f64 {
        let at = k * header.width;
        match header.width {
            4 => f64::from(f32::from_le_bytes(data[at..at + 4].try_into().expect("4 bytes"))),
            _ => f64::from_le_bytes(data[at..at + 8].try_into().expect("8 bytes")),
        }
    };
    // Row `i`, column `j`: C order stores rows whole, Fortran order columns.
    let index = |i: usize, j: usize| if header.fortran { j * header.rows + i } else { 3 * i + j };
    let mut points = Vec::with_capacity(header.rows);
    for i in 0..header.rows {
        let mut xyz = [0f32; 3];
        for (j, slot) in xyz.iter_mut().enumerate() {
            let v = value(index(i, j));
            if !v.is_finite() || v.abs() > f64::from(MAX_QUERY_COORDINATE) {
                return Err(syntax(
                    path,
                    None,
                    format!("point {i} has the coordinate {v}, not a finite number within ±{MAX_QUERY_COORDINATE:e}"),
                ));
            }
            *slot = v as f32;
        }
        points.push(Vec3::from_array(xyz));
    }
    Ok(points)
}

/// What the header of a `.npy` file says.
struct Header {
    /// Bytes per value: 4 or 8.
    width: usize,
    fortran: bool,
    rows: usize,
    data_start: usize,
}

impl Header {
    fn parse(bytes: &[u8], path: &Path) -> Result<Self, LoadError> {
        let fail = |message: String| syntax(path, None, message);
        if !bytes.starts_with(MAGIC) || bytes.len() < 10 {
            return Err(fail("not a .npy file (it does not start with \\x93NUMPY)".into()));
        }
        let (length, start): (usize, usize) = match bytes[6] {
            1 => (usize::from(u16::from_le_bytes([bytes[8], bytes[9]])), 10),
            2 | 3 if bytes.len() >= 12 => (
                u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
                12,
            ),
            version => return Err(fail(format!(".npy format version {version} is not one of 1, 2, 3"))),
        };
        let end = start
            .checked_add(length)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                truncated(
                    path,
                    None,
                    format!("the .npy header of {length} bytes runs past the file"),
                )
            })?;
        let dict = std::str::from_utf8(&bytes[start..end])
            .map_err(|_| fail("the .npy header is not text".into()))?
            .trim();
        let descr = value_of(dict, "descr").ok_or_else(|| fail(format!("no 'descr' in the .npy header {dict}")))?;
        let width = match descr.trim_matches(['\'', '"']) {
            "<f4" | "|f4" | "=f4" => 4,
            "<f8" | "|f8" | "=f8" => 8,
            other => {
                return Err(fail(format!(
                    "the .npy array holds '{other}'; points are little-endian float32 or float64 ('<f4', '<f8')"
                )));
            }
        };
        let fortran = match value_of(dict, "fortran_order") {
            Some("False") => false,
            Some("True") => true,
            _ => {
                return Err(fail(format!(
                    "no 'fortran_order' True or False in the .npy header {dict}"
                )));
            }
        };
        let shape = value_of(dict, "shape").ok_or_else(|| fail(format!("no 'shape' in the .npy header {dict}")))?;
        let dimensions: Vec<&str> = shape
            .trim_start_matches('(')
            .trim_end_matches(')')
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        let rows = match dimensions[..] {
            [rows, "3"] => rows.parse::<usize>().ok(),
            _ => None,
        }
        .ok_or_else(|| fail(format!("the .npy array has shape {shape}; points are (N, 3)")))?;
        Ok(Self {
            width,
            fortran,
            rows,
            data_start: end,
        })
    }
}

/// The text of `key`'s value in a Python dict literal: a quoted string, a
/// word, or a parenthesized tuple.
fn value_of<'d>(dict: &'d str, key: &str) -> Option<&'d str> {
    let at = dict
        .find(&format!("'{key}'"))
        .or_else(|| dict.find(&format!("\"{key}\"")))?;
    let rest = dict[at + key.len() + 2..].trim_start().strip_prefix(':')?.trim_start();
    let end = if rest.starts_with('(') {
        rest.find(')')? + 1
    } else {
        rest.find([',', '}']).unwrap_or(rest.len())
    };
    Some(rest[..end].trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An `.npy` file as numpy writes it (version 1.0, header padded to a
    /// multiple of 64 bytes).
    fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let order = if fortran { "True" } else { "False" };
        let dict = format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape}, }}");
        let unpadded = 10 + dict.len() + 1;
        let header = format!("{dict}{}\n", " ".repeat(unpadded.next_multiple_of(64) - unpadded));
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        out.extend(data);
        out
    }

    fn f32s(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn f64s(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    #[test]
    fn both_widths_and_orders() {
        let p = Path::new("p.npy");
        let expected = [Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.5)];
        let c32 = npy("<f4", false, "(2, 3)", &f32s(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.5]));
        let f64_fortran = npy("<f8", true, "(2, 3)", &f64s(&[1.0, 4.0, 2.0, 5.0, 3.0, 6.5]));
        assert_eq!(parse_npy_points(&c32, p).unwrap(), expected);
        assert_eq!(parse_npy_points(&f64_fortran, p).unwrap(), expected);
        // float64 rounds to the nearest f32.
        let x = 0.1f64;
        let rounded = parse_npy_points(&npy("<f8", false, "(1, 3)", &f64s(&[x, x, x])), p).unwrap();
        assert_eq!(rounded[0].x, x as f32);
        assert!(
            parse_npy_points(&npy("<f4", false, "(0, 3)", &[]), p)
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn bad_files_are_refused_with_what_was_found() {
        let p = Path::new("p.npy");
        let cases: [(Vec<u8>, &str); 8] = [
            (b"hello".to_vec(), "not a .npy file"),
            (npy("<i4", false, "(1, 3)", &[0; 12]), "holds '<i4'"),
            (npy(">f4", false, "(1, 3)", &[0; 12]), "holds '>f4'"),
            (npy("<f4", false, "(3,)", &[0; 12]), "has shape (3,)"),
            (npy("<f4", false, "(1, 4)", &[0; 16]), "has shape (1, 4)"),
            (
                npy("<f4", false, "(2, 3)", &[0; 12]),
                "needs 24 data bytes, the file holds 12",
            ),
            (npy("<f4", false, "(1, 3)", &[0; 13]), "1 bytes after"),
            (
                npy("<f4", false, "(1, 3)", &f32s(&[0.0, f32::NAN, 0.0])),
                "point 0 has the coordinate NaN",
            ),
        ];
        for (bytes, message) in cases {
            let e = parse_npy_points(&bytes, p).unwrap_err();
            assert!(e.to_string().contains(message), "{e} lacks {message}");
        }
        let mut header_past_end = npy("<f4", false, "(1, 3)", &[0; 12]);
        header_past_end[8] = 0xff;
        assert!(parse_npy_points(&header_past_end[..100], p).is_err());
        let mut version = npy("<f4", false, "(1, 3)", &[0; 12]);
        version[6] = 9;
        assert!(
            parse_npy_points(&version, p)
                .unwrap_err()
                .to_string()
                .contains("version 9")
        );
    }
}
