//! Exact integer arithmetic on floating-point inputs, for the decisions that
//! rounding cannot settle (touching in the triangle / box test, ties between
//! a ray's plane crossings).
//!
//! Every finite `f32` or `f64` is a dyadic rational `m · 2^e`. At the scale of
//! the smallest bit among a decision's inputs ([`common_scale`]) each input is
//! an integer, and so is every sum, difference and product of them: the
//! decision is made with no rounding at all. The integers are `i128` when the
//! inputs span few enough bits for the expression's degree (callers check the
//! span), and [`BigInt`] otherwise; decisions are written once, generic over
//! [`Exact`].

use num_bigint::BigInt;
use std::ops::{Add, Mul, Neg, Sub};

/// Integer arithmetic of the exact decisions: `i128` when the inputs' bits
/// fit (almost always: coordinates of one mesh and one grid span few
/// binades), [`BigInt`] otherwise. The decisions are written once for both.
pub(crate) trait Exact:
    Clone + Ord + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    fn zero() -> Self;
    /// `mantissa · 2^shift`.
    fn shifted(mantissa: i64, shift: u32) -> Self;
}

impl Exact for i128 {
    fn zero() -> Self {
        0
    }
    fn shifted(mantissa: i64, shift: u32) -> Self {
        (mantissa as i128) << shift
    }
}

impl Exact for BigInt {
    fn zero() -> Self {
        BigInt::ZERO
    }
    fn shifted(mantissa: i64, shift: u32) -> Self {
        BigInt::from(mantissa) << shift
    }
}

/// `x = mantissa · 2^exponent` with an odd mantissa (`None` for zero), for
/// a finite `x` (every `f32` and `f64` is such a dyadic rational).
pub(crate) fn parts(x: f64) -> Option<(i64, i32)> {
    debug_assert!(x.is_finite(), "exact arithmetic takes finite values, got {x}");
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = (bits & 0xf_ffff_ffff_ffff) as i64;
    // Subnormals are fraction · 2^-1074; normals (2^52 + fraction) · 2^(biased − 1075).
    let (mantissa, exponent) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), biased - 1075)
    };
    if mantissa == 0 {
        return None;
    }
    let zeros = mantissa.trailing_zeros();
    let signed = if bits >> 63 == 1 {
        -(mantissa >> zeros)
    } else {
        mantissa >> zeros
    };
    Some((signed, exponent + zeros as i32))
}

/// The common scale of `values`: the smallest exponent of their parts, and
/// the bits the largest needs as an integer at that scale.
pub(crate) fn common_scale(values: &[f64]) -> (i32, u32) {
    let mut low = i32::MAX;
    let mut high = i32::MIN;
    for &x in values {
        if let Some((mantissa, exponent)) = parts(x) {
            low = low.min(exponent);
            high = high.max(exponent + (64 - mantissa.unsigned_abs().leading_zeros()) as i32);
        }
    }
    if low == i32::MAX {
        (0, 0)
    } else {
        (low, (high - low) as u32)
    }
}

/// `x` as an integer at the scale `2^-low` (exact: `x` is a multiple of `2^low`).
pub(crate) fn integer<T: Exact>(x: f64, low: i32) -> T {
    match parts(x) {
        Some((mantissa, exponent)) => T::shifted(mantissa, (exponent - low) as u32),
        None => T::zero(),
    }
}

pub(crate) fn integers<T: Exact>(v: &[f64; 3], low: i32) -> [T; 3] {
    v.map(|x| integer(x, low))
}
