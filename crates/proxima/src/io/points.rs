//! Points and rays files: the query points of `proxima closest --points`,
//! `sdf --points` and `bench --points`, the rays of `raycast --rays`.

use super::read::{Limit, TextGuard, read_bounded};
use super::text::{Lines, show, syntax};
use super::{DEFAULT_MAX_LINE_BYTES, LoadOptions};
use crate::build::MAX_QUERY_COORDINATE;
use crate::error::{LoadError, LoadErrorKind};
use crate::math::Vec3;
use std::path::Path;

/// Reads a points file within the limits of `options` (as
/// [`load_with`](super::load_with) reads a mesh: streamed, bounded in size
/// and line length), then [`parse_points`] it; a `.npy` file (by its
/// extension) is read whole within the same size limits and
/// [`parse_npy_points`](super::parse_npy_points) it.
pub fn load_points(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Vec<Vec3>, LoadError> {
    let path = path.as_ref();
    let npy = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    if npy {
        return super::parse_npy_points(&read_bytes(path, options, TextGuard::binary())?, path);
    }
    parse_lines(
        &read_bytes(path, options, TextGuard::text(options.max_line_bytes))?,
        path,
        parse_point,
    )
}

/// Reads a rays file within the limits of `options`, then [`parse_rays`] it.
pub fn load_rays(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Vec<(Vec3, Vec3)>, LoadError> {
    let path = path.as_ref();
    parse_lines(
        &read_bytes(path, options, TextGuard::text(options.max_line_bytes))?,
        path,
        parse_ray,
    )
}

/// The bytes of a file, streamed and bounded in size by `options`, and
/// checked as they come by `guard` (line length, for text).
fn read_bytes(path: &Path, options: &LoadOptions, mut guard: TextGuard) -> Result<Vec<u8>, LoadError> {
    let file = std::fs::File::open(path).map_err(|e| LoadError::new(path, None, e))?;
    let metadata = file.metadata().map_err(|e| LoadError::new(path, None, e))?;
    let size = metadata.is_file().then_some(metadata.len());
    let budget = super::read::Budget {
        bytes: options.memory_budget,
    };
    read_bounded(
        file,
        Limit::Input(options.max_input_bytes),
        size,
        &mut guard,
        budget,
        path,
    )
}

/// Parses a rays file: one ray per line, `ox oy oz dx dy dz` separated by
/// commas and/or white space, with the rules of [`parse_points`] (comments,
/// blank lines, the origin's range, errors with their line). The direction
/// must be finite and not zero, nor so small that its reciprocal overflows
/// (as [`Ray::new`](crate::Ray::new) requires); it need not be unit length.
///
/// ```
/// use proxima::Vec3;
/// let rays = proxima::io::parse_rays(b"# origin, direction\n0 0 -1 0 0 1\n1,2,3,1,0,0\n", "r.rays".as_ref())?;
/// assert_eq!(rays[1], (Vec3::new(1.0, 2.0, 3.0), Vec3::X));
/// let e = proxima::io::parse_rays(b"0 0 0 1 0 0\n0 0 0 0 0 0\n", "r.rays".as_ref()).unwrap_err();
/// assert_eq!(e.line, Some(2));
/// # Ok::<(), proxima::LoadError>(())
/// ```
pub fn parse_rays(bytes: &[u8], path_for_errors: &Path) -> Result<Vec<(Vec3, Vec3)>, LoadError> {
    TextGuard::text(DEFAULT_MAX_LINE_BYTES).feed(bytes, path_for_errors)?;
    parse_lines(bytes, path_for_errors, parse_ray)
}

/// Parses a points file: one point per line, three numbers separated by commas
/// and/or white space; `#` comments and blank lines are skipped, as is a
/// leading UTF-8 byte order mark. Each coordinate must be finite and within
/// ±[`MAX_QUERY_COORDINATE`], the range where the trees' squared distances fit
/// `f32`. Errors carry the line: [`LoadErrorKind::Syntax`] for a line that is
/// not a point, [`LoadErrorKind::InvalidUtf8`], and the text checks of
/// [`parse`](super::parse) ([`LoadErrorKind::NotText`],
/// [`LoadErrorKind::LineTooLong`]).
///
/// ```
/// let points = proxima::io::parse_points(b"# x y z\n1,2,3\n4 5 6\n", "q.pts".as_ref())?;
/// assert_eq!(points, [proxima::Vec3::new(1.0, 2.0, 3.0), proxima::Vec3::new(4.0, 5.0, 6.0)]);
/// let e = proxima::io::parse_points(b"1,2,3\n1 2\n", "q.pts".as_ref()).unwrap_err();
/// assert_eq!(e.line, Some(2));
/// # Ok::<(), proxima::LoadError>(())
/// ```
pub fn parse_points(bytes: &[u8], path_for_errors: &Path) -> Result<Vec<Vec3>, LoadError> {
    TextGuard::text(DEFAULT_MAX_LINE_BYTES).feed(bytes, path_for_errors)?;
    parse_lines(bytes, path_for_errors, parse_point)
}

/// Every line that is not blank or a comment, parsed by `parse`.
fn parse_lines<R>(bytes: &[u8], path: &Path, parse: fn(&str) -> Result<R, String>) -> Result<Vec<R>, LoadError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    // A line takes at least six bytes ("1 2 3\n").
    let mut out = Vec::with_capacity(bytes.len() / 6);
    for (number, line) in Lines::new(bytes, 1) {
        let Ok(line) = std::str::from_utf8(line) else {
            return Err(LoadError::new(path, Some(number), LoadErrorKind::InvalidUtf8));
        };
        let content = line.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        out.push(parse(content).map_err(|message| syntax(path, Some(number), message))?);
    }
    Ok(out)
}

/// `ox oy oz dx dy dz` as a ray: the origin within the query bound, the
/// direction usable by [`Ray::new`](crate::Ray::new).
fn parse_ray(text: &str) -> Result<(Vec3, Vec3), String> {
    let expected = || {
        format!(
            "expected six numbers OX,OY,OZ,DX,DY,DZ, got '{}'",
            show(text.as_bytes())
        )
    };
    let mut numbers = text.split([',', ' ', '\t']).filter(|s| !s.is_empty());
    let mut values = [0f32; 6];
    for (k, slot) in values.iter_mut().enumerate() {
        let number = numbers.next().ok_or_else(expected)?;
        *slot = if k < 3 { coordinate(number)? } else { finite(number)? };
    }
    if numbers.next().is_some() {
        return Err(expected());
    }
    let origin = Vec3::new(values[0], values[1], values[2]);
    let direction = Vec3::new(values[3], values[4], values[5]);
    crate::Ray::new(origin, direction).map_err(|e| e.to_string())?;
    Ok((origin, direction))
}

/// A finite number.
fn finite(number: &str) -> Result<f32, String> {
    let value: f32 = number
        .parse()
        .map_err(|_| format!("'{}' is not a number", show(number.as_bytes())))?;
    if !value.is_finite() {
        return Err(format!("'{}' is not a finite number", show(number.as_bytes())));
    }
    Ok(value)
}

/// A finite number within the query bound.
fn coordinate(number: &str) -> Result<f32, String> {
    let value = finite(number)?;
    if value.abs() > MAX_QUERY_COORDINATE {
        return Err(format!(
            "'{}' is beyond ±{MAX_QUERY_COORDINATE:e}, where squared distances overflow f32",
            show(number.as_bytes())
        ));
    }
    Ok(value)
}

/// `X,Y,Z` (commas and/or white space) as a point within the query bound.
fn parse_point(text: &str) -> Result<Vec3, String> {
    let expected = || format!("expected three numbers X,Y,Z, got '{}'", show(text.as_bytes()));
    let mut numbers = text.split([',', ' ', '\t']).filter(|s| !s.is_empty());
    let mut xyz = [0f32; 3];
    for slot in &mut xyz {
        *slot = coordinate(numbers.next().ok_or_else(expected)?)?;
    }
    if numbers.next().is_some() {
        return Err(expected());
    }
    Ok(Vec3::from_array(xyz))
}
