//! Hash functions for cell keys.
//!
//! A cell key `(i, j, k)` is hashed by writing its three indices with
//! [`Hasher::write_i64`], in order. Two [`BuildHasher`]s are provided:
//!
//! - [`ClassicHash`], the default: the classic spatial hash
//!   `h = 131071·i + 524287·j + 8191·k` (wrapping), kept for compatibility with
//!   the classic design and for reproducing its numbers.
//! - [`FastHash`]: the same sum passed through a multiply–xorshift finalizer.
//!
//! The standard `HashMap` (SwissTable) takes the bucket from the low bits of
//! the hash and a 7-bit tag from the top bits. The classic sum of small indices
//! has top bits that are all 0 (or all 1 for negative sums), so every key in a
//! probe group matches the tag and must be compared in full; the finalizer
//! spreads the sum over all 64 bits for two more multiplications per key.
//! `docs/grid.md` gives the measurement on the real meshes.

use std::hash::{BuildHasher, Hasher};

/// The classic multipliers, in the order i, j, k.
const CLASSIC: [u64; 3] = [131_071, 524_287, 8_191];

/// The sum state shared by both hashers: each `write_i64` adds the next
/// multiplier times the value.
#[derive(Clone, Copy, Debug, Default)]
struct Sum {
    h: u64,
    n: usize,
}

impl Sum {
    #[inline]
    fn add(&mut self, v: u64) {
        self.h = self.h.wrapping_add(CLASSIC[self.n % 3].wrapping_mul(v));
        self.n += 1;
    }

    /// Bytes written by keys other than cells: whole 8-byte words as values,
    /// then the tail as one value.
    fn bytes(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut word = [0u8; 8];
            word[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(word));
        }
    }
}

/// [`BuildHasher`] of the classic spatial hash `131071·i + 524287·j + 8191·k`.
///
/// ```
/// use proxima::grid::ClassicHash;
/// use std::hash::{BuildHasher, Hasher};
/// let mut h = ClassicHash.build_hasher();
/// h.write_i64(1);
/// h.write_i64(-2);
/// h.write_i64(3);
/// assert_eq!(h.finish(), (131071i64 - 2 * 524287 + 3 * 8191) as u64);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClassicHash;

/// The hasher of [`ClassicHash`].
#[derive(Clone, Copy, Debug, Default)]
pub struct ClassicHasher(Sum);

impl BuildHasher for ClassicHash {
    type Hasher = ClassicHasher;
    #[inline]
    fn build_hasher(&self) -> ClassicHasher {
        ClassicHasher::default()
    }
}

impl Hasher for ClassicHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0.h
    }
    #[inline]
    fn write_i64(&mut self, v: i64) {
        self.0.add(v as u64);
    }
    fn write(&mut self, bytes: &[u8]) {
        self.0.bytes(bytes);
    }
}

/// [`BuildHasher`] of the classic sum followed by a multiply–xorshift
/// finalizer, which spreads it over all 64 bits.
///
/// ```
/// use proxima::grid::FastHash;
/// use std::hash::{BuildHasher, Hasher};
/// let hash = |i: i64| {
///     let mut h = FastHash.build_hasher();
///     [i, 0, 0].iter().for_each(|&v| h.write_i64(v));
///     h.finish()
/// };
/// // Neighbouring cells differ in their top bits too.
/// assert_ne!(hash(0) >> 57, hash(1) >> 57);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FastHash;

/// The hasher of [`FastHash`].
#[derive(Clone, Copy, Debug, Default)]
pub struct FastHasher(Sum);

impl BuildHasher for FastHash {
    type Hasher = FastHasher;
    #[inline]
    fn build_hasher(&self) -> FastHasher {
        FastHasher::default()
    }
}

impl Hasher for FastHasher {
    #[inline]
    fn finish(&self) -> u64 {
        let mut x = self.0.h;
        x ^= x >> 32;
        x = x.wrapping_mul(0xd6e8_feb8_6659_fd93);
        x ^= x >> 32;
        x = x.wrapping_mul(0xd6e8_feb8_6659_fd93);
        x ^ (x >> 32)
    }
    #[inline]
    fn write_i64(&mut self, v: i64) {
        self.0.add(v as u64);
    }
    fn write(&mut self, bytes: &[u8]) {
        self.0.bytes(bytes);
    }
}
