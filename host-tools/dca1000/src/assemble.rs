//! Frames from the DCA1000's packets: each packet's byte count says where its samples go in the
//! stream, so a frame is assembled by position whatever order the packets came in. A packet seen
//! before (same sequence number) is a duplicate and counted; one with a lower sequence number
//! than one already seen is reordered; sequence numbers never seen are lost. A frame is handed
//! on when it is whole, or once packets for frames [`LAG`] ahead arrive (or the stream ends):
//! then with its missing bytes zero-filled and counted, so it is never taken for a whole one.
//!
//! Memory: at most `LAG + 1` frames and a bounded set of recent sequence numbers.

use crate::packet::DataPacket;
use std::collections::{BTreeMap, BTreeSet, VecDeque};

/// Frames past the oldest unfinished one after which it is handed on incomplete.
pub const LAG: u64 = 2;
/// Frames ahead of the oldest unfinished one a packet may reach; farther is not a plausible
/// stream (a corrupt byte count) and the packet is dropped. It also bounds the frames one
/// packet can make the assembler hand on (and hold) at once.
pub const MAX_AHEAD: u64 = 8;
/// Sequence numbers remembered behind the highest, for telling duplicates from late packets.
pub const SEQ_WINDOW: u32 = 1 << 16;

/// One frame of the stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    /// Frame number from the start of the stream.
    pub index: u64,
    /// Its bytes, as `radar.bin` holds them; missing ones are zero. The last frame of a stream
    /// that ended mid-frame is shorter than a frame.
    pub bytes: Vec<u8>,
    /// Bytes that never arrived (zero-filled).
    pub missing: usize,
}

impl Frame {
    /// Whether every byte of a whole frame of `frame_bytes` arrived: only such a frame may be
    /// processed as a frame.
    pub fn is_whole(&self, frame_bytes: usize) -> bool {
        self.missing == 0 && self.bytes.len() == frame_bytes
    }
}

/// What the assembler saw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Packets taken (not duplicates).
    pub packets: u64,
    /// Sample bytes taken.
    pub bytes: u64,
    /// Packets whose sequence number was seen before (dropped).
    pub duplicates: u64,
    /// Packets that arrived after one with a higher sequence number.
    pub reordered: u64,
    /// Packets for frames already handed on (dropped).
    pub late: u64,
    /// Packets whose byte count points implausibly far ahead (dropped).
    pub implausible: u64,
    /// Frames handed on whole.
    pub whole_frames: u64,
    /// Frames handed on with missing bytes or cut short.
    pub incomplete_frames: u64,
    /// Lowest and highest sequence number taken.
    pub seq_range: Option<(u32, u32)>,
}

impl Stats {
    /// Sequence numbers between the lowest and highest taken that never arrived (late ones
    /// arrived).
    pub fn lost(&self) -> u64 {
        self.seq_range.map_or(0, |(lo, hi)| {
            (u64::from(hi) - u64::from(lo) + 1).saturating_sub(self.packets + self.late)
        })
    }
}

/// A frame being filled: its bytes and the byte ranges received (sorted, disjoint).
struct Pending {
    bytes: Vec<u8>,
    ranges: Vec<(usize, usize)>,
    filled: usize,
}

impl Pending {
    fn new(frame_bytes: usize) -> Self {
        Self {
            bytes: vec![0; frame_bytes],
            ranges: Vec::new(),
            filled: 0,
        }
    }

    /// Copies `data` to `at`, counting only bytes not received before. O(ranges).
    fn put(&mut self, at: usize, data: &[u8]) {
        let (start, end) = (at, at + data.len());
        let mut new = end - start;
        for &(s, e) in &self.ranges {
            let (a, b) = (s.max(start), e.min(end));
            if a < b {
                new -= b - a;
            }
        }
        self.bytes[start..end].copy_from_slice(data);
        self.filled += new;
        // Merge the range in.
        self.ranges.push((start, end));
        self.ranges.sort_unstable();
        let mut merged: Vec<(usize, usize)> = Vec::with_capacity(self.ranges.len());
        for &(s, e) in &self.ranges {
            match merged.last_mut() {
                Some(last) if s <= last.1 => last.1 = last.1.max(e),
                _ => merged.push((s, e)),
            }
        }
        self.ranges = merged;
    }
}

/// Assembles frames of `frame_bytes` from data packets.
pub struct Assembler {
    frame_bytes: u64,
    pending: BTreeMap<u64, Pending>,
    /// The oldest frame not yet handed on.
    next: u64,
    /// One past the highest stream byte received.
    end: u64,
    seen: BTreeSet<u32>,
    ready: VecDeque<Frame>,
    stats: Stats,
}

impl Assembler {
    /// An assembler for frames of `frame_bytes` (≥ 1).
    pub fn new(frame_bytes: usize) -> Self {
        Self {
            frame_bytes: frame_bytes.max(1) as u64,
            pending: BTreeMap::new(),
            next: 0,
            end: 0,
            seen: BTreeSet::new(),
            ready: VecDeque::new(),
            stats: Stats::default(),
        }
    }

    /// What it saw so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Takes one packet. O(payload + frames touched · ranges).
    pub fn push(&mut self, p: &DataPacket<'_>) {
        if !self.seen.insert(p.seq) {
            self.stats.duplicates += 1;
            return;
        }
        if let Some((_, hi)) = self.stats.seq_range {
            if p.seq < hi {
                self.stats.reordered += 1;
            }
            // Forget sequence numbers far behind the highest.
            let floor = hi.max(p.seq).saturating_sub(SEQ_WINDOW);
            while self.seen.first().is_some_and(|&s| s < floor) {
                self.seen.pop_first();
            }
        }
        let fb = self.frame_bytes;
        let (start, end) = (p.offset, p.offset.saturating_add(p.payload.len() as u64));
        if (end - 1) / fb >= self.next + MAX_AHEAD {
            self.stats.implausible += 1;
            return;
        }
        if end <= self.next * fb {
            self.stats.late += 1;
            return;
        }
        self.stats.packets += 1;
        self.stats.seq_range = Some(match self.stats.seq_range {
            Some((lo, hi)) => (lo.min(p.seq), hi.max(p.seq)),
            None => (p.seq, p.seq),
        });
        self.stats.bytes += p.payload.len() as u64;
        self.end = self.end.max(end);
        // The part of the payload in each frame it spans (not the frames handed on).
        let mut at = start.max(self.next * fb);
        while at < end {
            let k = at / fb;
            let stop = ((k + 1) * fb).min(end);
            let data = &p.payload[(at - start) as usize..(stop - start) as usize];
            self.pending
                .entry(k)
                .or_insert_with(|| Pending::new(fb as usize))
                .put((at - k * fb) as usize, data);
            at = stop;
        }
        self.hand_on(false);
    }

    /// The stream ended: every frame still open is handed on (the last one cut at the last
    /// byte received).
    pub fn finish(&mut self) {
        self.hand_on(true);
    }

    /// The next frame handed on, oldest first.
    pub fn pop(&mut self) -> Option<Frame> {
        self.ready.pop_front()
    }

    /// Hands on, in order, every frame that is whole, that frames `LAG` ahead have overtaken,
    /// or (at the end of the stream) that holds any byte.
    fn hand_on(&mut self, ending: bool) {
        let fb = self.frame_bytes;
        let newest = self.end.div_ceil(fb);
        loop {
            let whole = self
                .pending
                .get(&self.next)
                .is_some_and(|p| p.filled as u64 == fb);
            let overtaken = self.next + LAG < newest;
            let left = ending && self.next < newest;
            if !(whole || overtaken || left) {
                return;
            }
            let mut p = self
                .pending
                .remove(&self.next)
                .unwrap_or_else(|| Pending::new(fb as usize));
            // A stream that ends mid-frame: that frame is as long as what was sent of it.
            let len = if ending && self.next + 1 == newest && !self.end.is_multiple_of(fb) {
                (self.end % fb) as usize
            } else {
                fb as usize
            };
            p.bytes.truncate(len);
            let received: usize = p.ranges.iter().map(|&(s, e)| e.min(len) - s.min(len)).sum();
            let frame = Frame {
                index: self.next,
                missing: len - received,
                bytes: p.bytes,
            };
            if frame.is_whole(fb as usize) {
                self.stats.whole_frames += 1;
            } else {
                self.stats.incomplete_frames += 1;
            }
            self.ready.push_back(frame);
            self.next += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Packets as (sequence number, offset, payload).
    type Packets = Vec<(u32, u64, Vec<u8>)>;

    /// A stream of `n` bytes (distinct values) as packets of `size`, sequence numbers from 1.
    fn packets(n: usize, size: usize) -> (Vec<u8>, Packets) {
        let stream: Vec<u8> = (0..n).map(|i| (i * 7 + i / 251) as u8).collect();
        let packets = stream
            .chunks(size)
            .enumerate()
            .map(|(i, c)| ((i + 1) as u32, (i * size) as u64, c.to_vec()))
            .collect();
        (stream, packets)
    }

    fn run(frame: usize, list: &[(u32, u64, Vec<u8>)]) -> (Vec<Frame>, Stats) {
        let mut a = Assembler::new(frame);
        let mut out = Vec::new();
        for (seq, offset, payload) in list {
            a.push(&DataPacket {
                seq: *seq,
                offset: *offset,
                payload,
            });
            out.extend(std::iter::from_fn(|| a.pop()));
        }
        a.finish();
        out.extend(std::iter::from_fn(|| a.pop()));
        (out, a.stats())
    }

    #[test]
    fn in_order_packets_give_the_stream_frame_by_frame() {
        // Packets of 1456 bytes straddle frames of 4000.
        let (stream, list) = packets(5 * 4000, 1456);
        let (frames, stats) = run(4000, &list);
        assert_eq!(frames.len(), 5);
        for f in &frames {
            assert!(f.is_whole(4000), "{}", f.index);
            let at = f.index as usize * 4000;
            assert_eq!(f.bytes, stream[at..at + 4000]);
        }
        assert_eq!((stats.lost(), stats.duplicates, stats.reordered), (0, 0, 0));
        assert_eq!(stats.whole_frames, 5);
    }

    #[test]
    fn reordered_and_duplicated_packets_change_nothing_but_the_counters() {
        let (stream, mut list) = packets(6 * 3000, 1000);
        list.swap(4, 5);
        list.swap(9, 11);
        let dup = list[7].clone();
        list.insert(9, dup);
        let (frames, stats) = run(3000, &list);
        let joined: Vec<u8> = frames.iter().flat_map(|f| f.bytes.clone()).collect();
        assert_eq!(joined, stream);
        assert!(frames.iter().all(|f| f.is_whole(3000)));
        // Seq 5 after 6; seq 11 and 10 after 12.
        assert_eq!((stats.duplicates, stats.reordered, stats.lost()), (1, 3, 0));
    }

    #[test]
    fn a_lost_packet_leaves_a_zero_filled_flagged_frame_and_the_rest_whole() {
        let (stream, mut list) = packets(6 * 3000, 1000);
        list.remove(7); // bytes 7000..8000, frame 2
        let (frames, stats) = run(3000, &list);
        assert_eq!(frames.len(), 6);
        let bad = &frames[2];
        assert!(!bad.is_whole(3000) && bad.missing == 1000);
        assert!(bad.bytes[1000..2000].iter().all(|&b| b == 0));
        assert_eq!(bad.bytes[..1000], stream[6000..7000]);
        assert!(
            frames
                .iter()
                .filter(|f| f.index != 2)
                .all(|f| f.is_whole(3000))
        );
        assert_eq!((stats.lost(), stats.incomplete_frames), (1, 1));
        // A whole frame lost still takes its place in the numbering.
        let (_, mut list) = packets(6 * 3000, 1000);
        list.drain(6..9);
        let (frames, _) = run(3000, &list);
        assert_eq!(frames[2].missing, 3000);
        assert_eq!(
            frames.iter().map(|f| f.index).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4, 5]
        );
    }

    #[test]
    fn a_stream_ending_mid_frame_gives_what_was_sent() {
        let (stream, list) = packets(16384, 1456);
        let (frames, _) = run(131_072, &list);
        assert_eq!(frames.len(), 1);
        assert_eq!(frames[0].bytes, stream);
        assert!(!frames[0].is_whole(131_072));
    }

    #[test]
    fn late_and_implausible_packets_are_dropped_and_counted() {
        let (_, mut list) = packets(8 * 1000, 500);
        let early = list[0].clone();
        list.push((99, early.1, early.2.clone())); // frame 0, long handed on
        list.push((100, 1000 * 1000, vec![1; 10])); // 1000 frames ahead
        let (frames, stats) = run(1000, &list);
        assert_eq!(frames.len(), 8);
        assert_eq!((stats.late, stats.implausible), (1, 1));
    }
}
