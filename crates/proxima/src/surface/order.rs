//! Batches of surface answers taken in the order of their triangles, so
//! that the mesh's arrays are read nearly in order.

use crate::query::sort_by_code;
use rayon::prelude::*;

/// Results computed in the order of their triangles and read in input
/// order ([`in_triangle_order_blocks`]): no copy of them is made in input
/// order, since a caller that copies them into columns of its own reads
/// them once anyway, and a scatter into input order costs a cache miss per
/// result written (docs/perf-log.md).
#[derive(Clone, Debug)]
pub struct TriangleOrdered<T> {
    /// The results in triangle order.
    values: Vec<T>,
    /// Where result `i` (in input order) is in `values`.
    rank: Vec<u32>,
}

impl<T> TriangleOrdered<T> {
    /// Result `i`, in input order.
    ///
    /// # Panics
    /// When `i` is not below [`len`](Self::len).
    #[inline]
    pub fn get(&self, i: usize) -> &T {
        &self.values[self.rank[i] as usize]
    }

    /// The number of results.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The results in input order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &T> + '_ {
        self.rank.iter().map(|&k| &self.values[k as usize])
    }

    /// The results in input order, copied.
    pub fn to_vec(&self) -> Vec<T>
    where
        T: Clone,
    {
        self.iter().cloned().collect()
    }
}

/// The results of the answers `0..triangles.len()`, on all cores, computed
/// in the order of their triangles (`triangles[i]`, `u32::MAX` for none,
/// last), ties in input order: the mesh's arrays are then read nearly in
/// order rather than at random (surface points of 100k queries on an
/// 871k-triangle mesh were 3.5× cheaper so than in input order).
/// `work(block, out)` gets the indices of up to 1,024 answers in that order
/// and writes their results to `out` (as long as the block, filled with
/// `empty`), so that it can gather what the whole block reads before
/// computing any of it (cache misses in flight together).
///
/// ```
/// use proxima::surface::in_triangle_order_blocks;
/// let tens = |block: &[u32], out: &mut [u32]| {
///     for (o, &i) in out.iter_mut().zip(block) {
///         *o = i * 10;
///     }
/// };
/// let results = in_triangle_order_blocks(&[7, 2, u32::MAX, 2], 0, tens);
/// assert_eq!(results.to_vec(), [0, 10, 20, 30]);
/// assert_eq!(*results.get(2), 20);
/// ```
pub fn in_triangle_order_blocks<T: Clone + Send + Sync>(
    triangles: &[u32],
    empty: T,
    work: impl Fn(&[u32], &mut [T]) + Sync,
) -> TriangleOrdered<T> {
    let order = triangle_order(triangles);
    let mut values = vec![empty; order.len()];
    values
        .par_chunks_mut(BLOCK)
        .zip(order.par_chunks(BLOCK))
        .for_each(|(out, block)| work(block, out));
    let mut rank = vec![0; order.len()];
    for (k, &i) in order.iter().enumerate() {
        rank[i as usize] = k as u32;
    }
    TriangleOrdered { values, rank }
}

/// Results worked per task of [`in_triangle_order_blocks`].
const BLOCK: usize = 1024;

/// The answers `0..triangles.len()` by triangle, ties in input order,
/// `u32::MAX` (none) last: radix-sorted on as many bits as the largest
/// triangle has, "none" just past it.
fn triangle_order(triangles: &[u32]) -> Vec<u32> {
    let last = triangles.iter().filter(|&&t| t != u32::MAX).max().map_or(0, |&t| t + 1);
    let keyed = triangles
        .iter()
        .enumerate()
        .map(|(i, &t)| (t.min(last), i as u32))
        .collect();
    sort_by_code(keyed, u32::BITS - last.leading_zeros())
        .into_iter()
        .map(|(_, i)| i)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;
    use std::sync::Mutex;

    /// Each answer is worked once, in the order of a stable sort by
    /// triangle (none last), and comes back in input order: over few and
    /// many triangles, ids past 2^30 and answers without a triangle.
    #[test]
    fn answers_are_worked_by_triangle_and_read_in_input_order() {
        let mut rng = Rng::new(3);
        for (n, range) in [
            (0usize, 1u64),
            (1, 1),
            (3000, 5),
            (3000, 1 << 20),
            (5000, 1 << 31),
            (5000, 1 << 32),
        ] {
            let triangles: Vec<u32> = (0..n)
                .map(|_| match rng.below(5) {
                    0 => u32::MAX,
                    _ => (rng.next_u64() % range) as u32,
                })
                .collect();
            // On one thread, the blocks come in order: the visits follow
            // the order itself.
            let visited = Mutex::new(Vec::new());
            let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            let record = |block: &[u32], out: &mut [(usize, u32)]| {
                for (o, &i) in out.iter_mut().zip(block) {
                    visited.lock().unwrap().push(i as usize);
                    *o = (i as usize, triangles[i as usize]);
                }
            };
            let out = one.install(|| in_triangle_order_blocks(&triangles, (usize::MAX, 0), record).to_vec());
            assert_eq!(out, triangles.iter().copied().enumerate().collect::<Vec<_>>());
            let mut expected: Vec<usize> = (0..n).collect();
            expected.sort_by_key(|&i| (triangles[i] == u32::MAX, triangles[i]));
            assert_eq!(visited.into_inner().unwrap(), expected);
            // By blocks, on the default pool: the same results, each block
            // in triangle order.
            let work = |block: &[u32], out: &mut [(usize, u32)]| {
                assert!(block.len() <= BLOCK && block.len() == out.len());
                assert!(
                    block
                        .windows(2)
                        .all(|w| (triangles[w[0] as usize], w[0]) < (triangles[w[1] as usize], w[1]))
                );
                for (o, &i) in out.iter_mut().zip(block) {
                    *o = (i as usize, triangles[i as usize]);
                }
            };
            let blocks = in_triangle_order_blocks(&triangles, (usize::MAX, 0), work);
            assert_eq!(blocks.len(), n);
            assert_eq!(blocks.to_vec(), out);
            assert!((0..n).all(|i| *blocks.get(i) == out[i]));
        }
    }
}
