//! The SIMD layer the wide trees and the signed distance field share: the
//! AVX2 token, triangle packets and their lane kernels.
//!
//! A [`TrianglePacket`] holds up to four triangles of a leaf in structure of
//! arrays form; its closest-point and ray tests (`packet.rs`, `f32x4`) repeat
//! the scalar routines operation for operation, so each lane is bit for bit
//! the scalar answer. On CPUs with AVX2 (detected at run time,
//! [`detect_avx2`]) two packets are tested at once on 256-bit lanes
//! (`avx2.rs`), with the same bits; work that should be compiled for AVX2
//! as a whole runs through [`Avx2::run`] and an [`Avx2Task`]. `lanes.rs`
//! hands a packet's ray hits to a query's visitor.
//!
//! `avx2.rs` is one of the crate's two modules with `unsafe` code (the
//! other is the ray tree's node test, `ray_tree/avx2.rs`).

#[cfg(target_arch = "x86_64")]
mod avx2;
mod lanes;
mod packet;

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::{Avx2, Avx2Task, V8, lane_of};
pub(crate) use lanes::{offer_lanes, offer_packet};
#[cfg(test)]
pub(crate) use packet::tests::triangles;
pub(crate) use packet::{TrianglePacket, V3, prefetch_packet};

/// The AVX2 token when this CPU has AVX2.
pub(crate) fn detect_avx2() -> Option<Avx2> {
    #[cfg(target_arch = "x86_64")]
    return Avx2::detect();
    #[cfg(not(target_arch = "x86_64"))]
    None
}

/// Stands for the AVX2 token where there is no AVX2: never made.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
pub(crate) enum Avx2 {}
