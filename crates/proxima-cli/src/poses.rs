//! Rigid poses on the command line: `--pose-a`/`--pose-b` (16 numbers, a
//! row-major 4x4 matrix) and `--poses FILE` (one such matrix per line).
//!
//! The numbers are parsed here; whether they make a rigid motion is the
//! library's decision ([`RigidPose::from_rows`]), whose message is printed
//! after the option's name or the file's line.

use anyhow::{Context, Result, bail};
use proxima::pair::{RigidPose, check_pose};
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// The 16 entries of a 4x4 matrix, by rows.
pub type Rows = [[f64; 4]; 4];

/// Longest line of a poses file: sixteen numbers take a few hundred bytes,
/// so anything longer is not a pose, and is refused before it is held.
const MAX_LINE_BYTES: usize = 64 << 10;

/// Parses 16 numbers separated by commas and/or white space into the rows of
/// a 4x4 matrix (row-major: `M00,M01,M02,M03,M10,…,M33`). NaN and infinities
/// parse; the pose check refuses them with its own message.
pub fn parse_rows(text: &str) -> Result<Rows, String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    if numbers.len() != 16 {
        return Err(format!(
            "expected 16 numbers (a 4x4 matrix [R t; 0 0 0 1] by rows), got {}",
            numbers.len()
        ));
    }
    let mut rows = [[0.0; 4]; 4];
    for (k, s) in numbers.iter().enumerate() {
        rows[k / 4][k % 4] = s.parse::<f64>().map_err(|_| format!("'{s}' is not a number"))?;
    }
    Ok(rows)
}

/// The pose of `rows`, or why it is not one, after `what` (`--pose-b`,
/// `poses.txt:3`): not rigid ([`proxima::pair::PoseError`]) or placed beyond
/// the library's range ([`check_pose`], called here so that a file's pose is
/// named by its line).
pub fn pose(rows: &Rows, what: &str) -> Result<RigidPose> {
    let pose = RigidPose::from_rows(*rows).with_context(|| what.to_string())?;
    check_pose(&pose, || what.to_string())?;
    Ok(pose)
}

/// The pose of an optional `--pose-a`/`--pose-b`: the identity when absent.
pub fn option_pose(rows: Option<&Rows>, option: &str) -> Result<RigidPose> {
    rows.map_or(Ok(RigidPose::IDENTITY), |rows| pose(rows, option))
}

/// Reads a poses file: one pose per line, 16 numbers separated by commas or
/// white space; blank lines and lines starting with `#` are skipped. The
/// poses are counted first, line by line, and checked against the memory
/// budget at `bytes_each` bytes per pose (what the command holds per pose)
/// before any is stored; a bad line is refused as `FILE:LINE: what`.
pub fn read_poses(path: &Path, bytes_each: usize) -> Result<Vec<RigidPose>> {
    let name = path.display().to_string();
    let mut count = 0usize;
    for_each_line(path, |_, _| {
        count += 1;
        Ok(())
    })?;
    proxima::budget::check_fits("--poses", &name, count as u128, bytes_each as u128)?;
    let mut poses = Vec::with_capacity(count);
    for_each_line(path, |number, line| {
        let what = format!("{name}:{number}");
        let rows = parse_rows(line).map_err(|e| anyhow::anyhow!("{what}: {e}"))?;
        poses.push(pose(&rows, &what)?);
        Ok(())
    })?;
    Ok(poses)
}

/// Calls `f(line number, text)` for each line of `path` that is neither blank
/// nor a `#` comment, holding one line at a time.
fn for_each_line(path: &Path, mut f: impl FnMut(usize, &str) -> Result<()>) -> Result<()> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).with_context(|| name.clone())?;
    let mut reader = BufReader::new(file);
    let mut bytes = Vec::new();
    let mut number = 0usize;
    loop {
        bytes.clear();
        number += 1;
        let read = (&mut reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut bytes)
            .with_context(|| name.clone())?;
        if read == 0 {
            return Ok(());
        }
        if bytes.len() > MAX_LINE_BYTES {
            bail!("{name}:{number}: the line is longer than {MAX_LINE_BYTES} bytes; a pose is 16 numbers");
        }
        let Ok(text) = std::str::from_utf8(&bytes) else {
            bail!("{name}:{number}: invalid UTF-8");
        };
        let text = text.trim_start_matches('\u{feff}').trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        f(number, text)?;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proxima::pair::MAX_TRANSLATION;

    #[test]
    fn sixteen_numbers_by_rows() {
        let rows = parse_rows("1,0,0,5 0,1,0,6, 0,0,1,7\t0,0,0,1").unwrap();
        assert_eq!(
            rows,
            [
                [1.0, 0.0, 0.0, 5.0],
                [0.0, 1.0, 0.0, 6.0],
                [0.0, 0.0, 1.0, 7.0],
                [0.0, 0.0, 0.0, 1.0]
            ]
        );
        let p = pose(&rows, "--pose-b").unwrap();
        assert_eq!(p.translation().to_array(), [5.0, 6.0, 7.0]);
        assert!(parse_rows("1,0,0").unwrap_err().contains("got 3"));
        assert!(
            parse_rows("1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,x")
                .unwrap_err()
                .contains("'x' is not a number")
        );
    }

    #[test]
    fn translations_at_the_bound_pass_and_one_ulp_beyond_do_not() {
        let at = |t: f64| {
            [
                [1.0, 0.0, 0.0, t],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]
        };
        assert!(pose(&at(MAX_TRANSLATION), "p").is_ok());
        assert!(pose(&at(-MAX_TRANSLATION), "p").is_ok());
        let e = pose(&at(MAX_TRANSLATION.next_up()), "--pose-b").unwrap_err();
        assert!(e.to_string().starts_with("--pose-b: a translation coordinate"), "{e}");
        assert!(pose(&at(-MAX_TRANSLATION.next_up()), "p").is_err());
    }
}
