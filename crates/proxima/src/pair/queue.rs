//! Pending work, nearest first, for best-first walks.

use std::collections::BinaryHeap;

/// Items taken out smallest key first: a binary heap of keys and slots over
/// a pool of the items themselves, so that a sift moves 16 bytes rather than
/// a whole item (the sifts of a heap of the walk's ~100-byte pending pairs
/// took a third of a far distance query: docs/perf-log.md). Freed slots are
/// reused, so a queue kept between walks allocates once.
///
/// Equal keys come out in no particular order.
#[derive(Debug)]
pub(crate) struct NearestQueue<T> {
    heap: BinaryHeap<Ranked>,
    pool: Vec<T>,
    free: Vec<u32>,
}

impl<T> Default for NearestQueue<T> {
    fn default() -> Self {
        Self {
            heap: BinaryHeap::new(),
            pool: Vec::new(),
            free: Vec::new(),
        }
    }
}

impl<T: Copy> NearestQueue<T> {
    /// Empties the queue, keeping its memory.
    pub(crate) fn clear(&mut self) {
        self.heap.clear();
        self.pool.clear();
        self.free.clear();
    }

    /// Adds `item` under `key` (NaN keys come out last).
    pub(crate) fn push(&mut self, key: f64, item: T) {
        let slot = match self.free.pop() {
            Some(slot) => {
                self.pool[slot as usize] = item;
                slot
            }
            None => {
                self.pool.push(item);
                (self.pool.len() - 1) as u32
            }
        };
        self.heap.push(Ranked { key, slot });
    }

    /// Takes out an item of the smallest key.
    pub(crate) fn pop(&mut self) -> Option<T> {
        let Ranked { slot, .. } = self.heap.pop()?;
        self.free.push(slot);
        Some(self.pool[slot as usize])
    }
}

/// A slot ordered by its key, smallest first in a max-heap.
#[derive(Clone, Copy, Debug)]
struct Ranked {
    key: f64,
    slot: u32,
}

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.key.total_cmp(&self.key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// Items come out in key order, interleaved pushes and pops included,
    /// as a sorted list would give them.
    #[test]
    fn items_come_out_smallest_key_first() {
        let mut rng = Rng::new(3);
        let mut queue = NearestQueue::default();
        let mut oracle: Vec<(f64, u32)> = Vec::new();
        for round in 0..3 {
            queue.clear();
            oracle.clear();
            for i in 0..500u32 {
                let key = f64::from(rng.range(0.0, 10.0)).floor();
                queue.push(key, (key, i));
                oracle.push((key, i));
                if i % 3 == round {
                    let (key, item) = queue.pop().unwrap();
                    let smallest = oracle.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
                    assert_eq!(key, smallest);
                    let at = oracle.iter().position(|x| *x == (key, item)).unwrap();
                    oracle.swap_remove(at);
                }
            }
            oracle.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (key, _) in &oracle {
                assert_eq!(queue.pop().unwrap().0, *key);
            }
            assert!(queue.pop().is_none());
        }
    }
}
