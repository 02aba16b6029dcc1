//! A value cached with the key it was computed from.

/// A value computed from a key and kept until it is asked for with another
/// key. The panel's derived values (query answers, tree nodes, frustum
/// selections...) are each one `Memo`, so a frame that changes nothing
/// recomputes nothing.
///
/// ```text
/// let mut squares = Memo::default();
/// assert_eq!(*squares.get_or_compute(3, |k| k * k), 9);
/// assert_eq!(squares.get(&3), Some(&9));
/// ```
#[derive(Debug)]
pub(crate) struct Memo<K, V> {
    entry: Option<(K, V)>,
}

impl<K, V> Default for Memo<K, V> {
    fn default() -> Self {
        Self { entry: None }
    }
}

impl<K: PartialEq, V> Memo<K, V> {
    /// The value for `key`, computed by `compute` unless it is the one cached.
    pub fn get_or_compute(&mut self, key: K, compute: impl FnOnce(&K) -> V) -> &V {
        if self.key() != Some(&key) {
            let value = compute(&key);
            self.entry = Some((key, value));
        }
        &self.entry.as_ref().expect("set above").1
    }

    /// The cached value if it was computed from `key`.
    pub fn get(&self, key: &K) -> Option<&V> {
        self.entry.as_ref().filter(|(k, _)| k == key).map(|(_, v)| v)
    }

    /// `true` when the cached value was computed from `key`.
    pub fn holds(&self, key: &K) -> bool {
        self.key() == Some(key)
    }

    /// The cached value, whatever its key (the last one computed).
    pub fn latest(&self) -> Option<&V> {
        self.entry.as_ref().map(|(_, v)| v)
    }

    /// The key of the cached value.
    pub fn key(&self) -> Option<&K> {
        self.entry.as_ref().map(|(k, _)| k)
    }

    /// Caches `value` as computed from `key` (a result that arrived from a
    /// background job).
    pub fn set(&mut self, key: K, value: V) {
        self.entry = Some((key, value));
    }
}

#[cfg(test)]
mod tests {
    use super::Memo;

    #[test]
    fn a_memo_recomputes_only_when_the_key_changes() {
        let mut calls = 0;
        let mut memo = Memo::default();
        for key in [2, 2, 3, 3, 2] {
            let value = *memo.get_or_compute(key, |k| {
                calls += 1;
                k * 10
            });
            assert_eq!(value, key * 10);
        }
        assert_eq!(calls, 3);
        assert_eq!((memo.get(&2), memo.get(&3)), (Some(&20), None));
        assert!(memo.holds(&2) && !memo.holds(&3));
        memo.set(7, 1);
        assert_eq!((memo.key(), memo.latest()), (Some(&7), Some(&1)));
        assert_eq!(Memo::<u8, u8>::default().latest(), None);
    }
}
