//! `proxima bench MESH [--query closest|sdf|rays] ...`: the options checked
//! against each other and the memory budget, then the one benchmark they
//! name (`closest.rs`, `sdf.rs`, `rays.rs`).

use crate::args::{Args, Peers, QueryKind, QuerySet};
use crate::closest::BYTES_PER_QUERY;
use crate::input::{memory_budget, thread_count};
use proxima::prelude::*;

/// Runs `proxima bench` (with `peers`, the `bench` binary): checks the
/// options against each other and against the memory budget, then runs the
/// benchmark `args.query` names and prints its table or JSON. Bad options
/// and inputs are one-line errors naming the option or the file; a
/// disagreement among proxima's structures is an error too (a bug).
pub fn run(args: Args, peers: Peers) -> anyhow::Result<()> {
    thread_count(args.threads)?;
    // Zero generated queries would leave every set empty and be reported as
    // a property of the mesh (no area, a point-sized box), not of the option.
    if args.points.is_none() && args.queries == 0 {
        anyhow::bail!("--queries must be at least 1");
    }
    if args.query == QueryKind::Sdf {
        if args.primitives.is_some_and(|kind| kind != PrimitiveKind::Faces) {
            anyhow::bail!("--query sdf measures signed distances to the faces; --primitives cannot change that");
        }
        return crate::sdf::run(&crate::sdf::Options {
            mesh: &args.mesh,
            queries: args.queries,
            points: args.points.as_deref(),
            sets: args
                .set
                .map_or(vec![QuerySet::Near, QuerySet::Uniform], |set| vec![set]),
            seed: args.seed,
            threads: args.threads,
            build: args.split.config(),
            split: args.split.name().to_string(),
            json: args.json,
        });
    }
    if args.query == QueryKind::Rays {
        if args.primitives.is_some_and(|kind| kind != PrimitiveKind::Faces) {
            anyhow::bail!("--query rays casts rays at the faces; --primitives cannot change that");
        }
        if args.points.is_some() || args.set.is_some() {
            anyhow::bail!("--query rays casts the BENCHMARKS rays set; --points and --set choose query points");
        }
    }
    let budget = memory_budget()?;
    if args.points.is_none() && args.queries as u128 * BYTES_PER_QUERY as u128 > budget as u128 {
        anyhow::bail!(
            "--queries {}: the query points and answers need about {} ({BYTES_PER_QUERY} bytes per query), more than the memory budget of {}",
            args.queries,
            proxima::budget::human_bytes(args.queries as u128 * BYTES_PER_QUERY as u128),
            proxima::budget::human_bytes(budget.into())
        );
    }
    if args.query == QueryKind::Rays {
        return crate::rays::run(
            &crate::rays::Options {
                mesh: &args.mesh,
                rays: args.queries,
                seed: args.seed,
                threads: args.threads,
                json: args.json,
            },
            peers,
        );
    }
    crate::closest::run(&args, peers)
}
