//! A bounded queue that drops its oldest entry when full, and counts what it dropped.
//!
//! The module's uplink and the host's receive side both use it: a slow link loses the oldest
//! results (stale anyway), never the newest, and the loss shows in the health counters.

use heapless::Deque;

/// At most `N` values; pushing onto a full queue drops the oldest.
#[derive(Debug)]
pub struct DropOldest<T, const N: usize> {
    items: Deque<T, N>,
    dropped: u32,
}

impl<T, const N: usize> Default for DropOldest<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T, const N: usize> DropOldest<T, N> {
    /// An empty queue.
    pub const fn new() -> Self {
        Self {
            items: Deque::new(),
            dropped: 0,
        }
    }

    /// Appends `value`, dropping the oldest entry if the queue is full. O(1).
    pub fn push(&mut self, value: T) {
        if let Err(value) = self.items.push_back(value) {
            let _ = self.items.pop_front();
            self.dropped = self.dropped.saturating_add(1);
            let _ = self.items.push_back(value);
        }
    }

    /// The oldest entry, left in place. O(1).
    pub fn front(&self) -> Option<&T> {
        self.items.front()
    }

    /// Removes the oldest entry. O(1).
    pub fn pop(&mut self) -> Option<T> {
        self.items.pop_front()
    }

    /// Entries waiting.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether nothing waits.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Entries dropped since creation.
    pub fn dropped(&self) -> u32 {
        self.dropped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_the_oldest_and_counts() {
        let mut q: DropOldest<u32, 3> = DropOldest::new();
        for i in 0..5 {
            q.push(i);
        }
        assert_eq!(q.dropped(), 2);
        assert_eq!(q.len(), 3);
        assert_eq!(
            [q.pop(), q.pop(), q.pop(), q.pop()],
            [Some(2), Some(3), Some(4), None]
        );
    }
}
