//! A map within a budget of bytes that lets go of what was used longest ago
//! first: the memory of the service's caches of finished work.

use std::collections::{BTreeMap, HashMap};
use std::hash::Hash;

/// Values by key, each weighed in bytes when put (as its cache counts it),
/// holding at most `budget` bytes: a value put beyond it pushes out the
/// values used longest ago.
#[derive(Debug)]
pub struct Lru<K, V> {
    entries: HashMap<K, Entry<V>>,
    /// The keys by their last use, longest ago first.
    by_use: BTreeMap<u64, K>,
    /// Counts uses: the stamp of the next.
    clock: u64,
    /// Bytes held.
    bytes: usize,
    /// Most bytes held.
    budget: usize,
}

#[derive(Debug)]
struct Entry<V> {
    value: V,
    bytes: usize,
    used: u64,
}

impl<K: Hash + Eq + Clone, V> Lru<K, V> {
    /// An empty map of at most `budget` bytes.
    pub fn new(budget: usize) -> Self {
        Lru {
            entries: HashMap::new(),
            by_use: BTreeMap::new(),
            clock: 0,
            bytes: 0,
            budget,
        }
    }

    /// The value of `key`, now the one used last.
    pub fn get(&mut self, key: &K) -> Option<&V> {
        let entry = self.entries.get_mut(key)?;
        self.by_use.remove(&entry.used);
        entry.used = self.clock;
        self.by_use.insert(self.clock, key.clone());
        self.clock += 1;
        Some(&entry.value)
    }

    /// Holds `value` of `bytes` as `key`'s (in place of any before), letting
    /// go of the values used longest ago to stay within the budget; a value
    /// larger than the whole budget is not held (`false`).
    pub fn put(&mut self, key: K, value: V, bytes: usize) -> bool {
        self.remove(&key);
        if bytes > self.budget {
            return false;
        }
        while self.bytes + bytes > self.budget {
            let Some((_, oldest)) = self.by_use.pop_first() else {
                break;
            };
            if let Some(gone) = self.entries.remove(&oldest) {
                self.bytes -= gone.bytes;
            }
        }
        self.by_use.insert(self.clock, key.clone());
        self.entries.insert(
            key,
            Entry {
                value,
                bytes,
                used: self.clock,
            },
        );
        self.clock += 1;
        self.bytes += bytes;
        true
    }

    /// Lets go of `key`'s value.
    pub fn remove(&mut self, key: &K) -> Option<V> {
        let gone = self.entries.remove(key)?;
        self.by_use.remove(&gone.used);
        self.bytes -= gone.bytes;
        Some(gone.value)
    }

    /// Lets go of every value.
    pub fn clear(&mut self) {
        self.entries.clear();
        self.by_use.clear();
        self.bytes = 0;
    }

    /// Values held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_value_used_longest_ago_goes_first() {
        let mut lru = Lru::new(30);
        lru.put("a", 1, 10);
        lru.put("b", 2, 10);
        lru.put("c", 3, 10);
        // "a" used again: "b" is now the one used longest ago.
        assert_eq!(lru.get(&"a"), Some(&1));
        assert!(lru.put("d", 4, 10));
        assert_eq!(lru.get(&"b"), None);
        assert_eq!(lru.get(&"a"), Some(&1));
        assert_eq!(lru.get(&"c"), Some(&3));
        assert_eq!(lru.get(&"d"), Some(&4));
        assert_eq!((lru.len(), lru.bytes()), (3, 30));
        // A large value pushes out as many as it needs: "a", then "c".
        assert!(lru.put("e", 5, 25));
        assert_eq!((lru.len(), lru.bytes()), (1, 25));
        assert_eq!(lru.get(&"e"), Some(&5));
    }

    #[test]
    fn the_budget_holds_through_replacing_removing_and_refusing() {
        let mut lru = Lru::new(100);
        lru.put(1, "x", 40);
        lru.put(1, "y", 50);
        assert_eq!(lru.get(&1), Some(&"y"));
        assert_eq!(lru.bytes(), 50);
        assert!(!lru.put(2, "too large", 101));
        assert_eq!((lru.len(), lru.bytes()), (1, 50));
        assert_eq!(lru.remove(&1), Some("y"));
        assert!(lru.is_empty());
        assert_eq!(lru.bytes(), 0);
        lru.put(3, "z", 60);
        lru.clear();
        assert_eq!((lru.len(), lru.bytes()), (0, 0));
        assert_eq!(lru.get(&3), None);
    }
}
