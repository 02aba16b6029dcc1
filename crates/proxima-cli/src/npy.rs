//! NumPy `.npy` (format version 1.0) and `.npz` writers for `float32` arrays:
//! the layouts numpy, PyTorch data loaders and DeepSDF-style training code read.

use std::io::{self, Write};

/// The `.npy` header of a little-endian `float32` array of `shape`: the
/// magic string, version 1.0, the header's length and a Python dict literal,
/// padded with spaces and ended by a newline so the data starts at a
/// multiple of 64 bytes (numpy's own alignment).
///
/// `fortran_order` says the first index varies fastest in the data (`[i, j,
/// k]` at `i + nx (j + ny k)`), as a grid evaluated x fastest is stored.
pub fn header(shape: &[usize], fortran_order: bool) -> Vec<u8> {
    let dimensions = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
        ),
    };
    let order = if fortran_order { "True" } else { "False" };
    let mut dict = format!("{{'descr': '<f4', 'fortran_order': {order}, 'shape': {dimensions}, }}");
    // Magic (6) + version (2) + length (2) + dict + newline, to a multiple of 64.
    let unpadded = 10 + dict.len() + 1;
    dict.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    dict.push('\n');
    let length = u16::try_from(dict.len()).expect("a header of a few dimensions is far below 64 KiB");
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend(length.to_le_bytes());
    bytes.extend(dict.as_bytes());
    bytes
}

/// The number of bytes of the `.npy` file of `values` in `shape`.
pub fn file_len(shape: &[usize], values: usize) -> u64 {
    header(shape, false).len() as u64 + 4 * values as u64
}

/// Writes `values` as a `.npy` array of `shape` (whose product must be
/// `values.len()`), little-endian `float32`.
pub fn write(out: &mut impl Write, shape: &[usize], fortran_order: bool, values: &[f32]) -> io::Result<()> {
    debug_assert_eq!(shape.iter().product::<usize>(), values.len());
    out.write_all(&header(shape, fortran_order))?;
    // Converted in blocks: one `write_all` per value costs more than the
    // conversion on grids of millions of cells.
    let mut block = Vec::with_capacity(4 * 16384);
    for chunk in values.chunks(16384) {
        block.clear();
        for value in chunk {
            block.extend_from_slice(&value.to_le_bytes());
        }
        out.write_all(&block)?;
    }
    Ok(())
}

/// The `.npz` archive (what `numpy.savez` makes) of the arrays `(name,
/// shape, values)`: a zip of stored (uncompressed) entries `name.npy`, each
/// in C order, made in memory for the caller to write.
///
/// The zip writer never sees the file: one that meets an I/O error (a full
/// disk) is left unfinished, finalizes again when dropped and prints a Rust
/// debug dump of the error on standard error, which `finish` cannot prevent
/// once it has failed. In memory only allocation can fail, and the caller
/// writes the bytes with an error of its own.
pub fn npz(arrays: &[(&str, &[usize], &[f32])]) -> zip::result::ZipResult<Vec<u8>> {
    // Each entry's bytes plus its local header and central directory record
    // (name, zip64 fields) and the end records, generously.
    let capacity = arrays
        .iter()
        .map(|&(name, shape, values)| file_len(shape, values.len()) + 2 * (name.len() as u64 + 128))
        .sum::<u64>()
        + 256;
    let buffer = Vec::with_capacity(usize::try_from(capacity).unwrap_or(0));
    let mut archive = zip::ZipWriter::new(io::Cursor::new(buffer));
    for &(name, shape, values) in arrays {
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored)
            // Zip64 records only where the entry needs them (4 GiB and over).
            .large_file(file_len(shape, values.len()) >= u64::from(u32::MAX));
        archive.start_file(format!("{name}.npy"), options)?;
        write(&mut archive, shape, false, values)?;
    }
    Ok(archive.finish()?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_align_the_data_to_64_bytes() {
        for shape in [&[0usize][..], &[7], &[100, 3], &[64, 64, 64], &[123456789, 3]] {
            let h = header(shape, false);
            assert_eq!(h.len() % 64, 0, "{shape:?}");
            assert_eq!(&h[..8], b"\x93NUMPY\x01\x00");
            assert_eq!(usize::from(u16::from_le_bytes([h[8], h[9]])), h.len() - 10);
            assert_eq!(h.last(), Some(&b'\n'));
        }
        let h = String::from_utf8(header(&[2, 3, 4], true)[10..].to_vec()).unwrap();
        assert!(h.starts_with("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3, 4), }"));
        let h = String::from_utf8(header(&[5], false)[10..].to_vec()).unwrap();
        assert!(h.contains("'shape': (5,)"), "{h}");
    }

    /// The archive is a zip of `name.npy` entries whose bytes are the
    /// arrays' `.npy` files, read back with the zip crate's reader.
    #[test]
    fn npz_holds_each_array_as_its_npy_file() {
        let points = [1.0, 2.0, 3.0, -4.0, 5.5, 6.0];
        let sdf = [0.25, -0.5];
        let bytes = npz(&[("points", &[2, 3], &points), ("sdf", &[2], &sdf)]).unwrap();
        let mut archive = zip::ZipArchive::new(io::Cursor::new(bytes)).unwrap();
        assert_eq!(archive.len(), 2);
        for (name, shape, values) in [("points.npy", &[2, 3][..], &points[..]), ("sdf.npy", &[2], &sdf)] {
            let mut expected = Vec::new();
            write(&mut expected, shape, false, values).unwrap();
            let mut entry = archive.by_name(name).unwrap();
            assert_eq!(entry.compression(), zip::CompressionMethod::Stored);
            let mut got = Vec::new();
            io::Read::read_to_end(&mut entry, &mut got).unwrap();
            assert_eq!(got, expected, "{name}");
        }
    }

    #[test]
    fn values_follow_the_header_little_endian() {
        let mut bytes = Vec::new();
        write(&mut bytes, &[2], false, &[1.0, -2.5]).unwrap();
        assert_eq!(bytes.len() as u64, file_len(&[2], 2));
        let data = header(&[2], false).len();
        assert_eq!(data, 128, "the dict does not fit the first 64 bytes");
        assert_eq!(&bytes[data..], [1f32.to_le_bytes(), (-2.5f32).to_le_bytes()].concat());
    }
}
