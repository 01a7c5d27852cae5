//! Instances from per-pixel classes: the 4-connected regions of each class other than the
//! background, as an instance mask with ids 1.. in raster order of each region's first pixel.

use crate::segmenter::ClassMap;

/// One instance: its id in the mask and its class index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    /// Id in the mask (1..).
    pub id: u16,
    /// Class index (≥ 1).
    pub class: u16,
    /// Pixels.
    pub pixels: usize,
}

/// Splits `map` into instances; regions smaller than `min_pixels` are left as background (0).
/// At most 65,535 instances (later regions stay background). O(w·h).
pub fn split(map: &ClassMap, min_pixels: usize) -> (Vec<u16>, Vec<Region>) {
    let (w, h) = (map.width, map.height);
    let mut mask = vec![0u16; w * h];
    let mut seen = vec![false; w * h];
    let mut regions = Vec::new();
    let mut stack = Vec::new();
    let mut members = Vec::new();
    for start in 0..w * h {
        let class = map.classes[start];
        if class == 0 || seen[start] {
            continue;
        }
        // Flood fill the region from its first pixel.
        members.clear();
        seen[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            members.push(i);
            let (x, y) = (i % w, i / w);
            let next = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ];
            for j in next.into_iter().flatten() {
                if !seen[j] && map.classes[j] == class {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if members.len() < min_pixels || regions.len() == usize::from(u16::MAX) {
            continue;
        }
        let id = regions.len() as u16 + 1;
        for &i in &members {
            mask[i] = id;
        }
        regions.push(Region {
            id,
            class,
            pixels: members.len(),
        });
    }
    (mask, regions)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_are_4_connected_per_class_and_small_ones_dropped() {
        // 1 1 0 2
        // 0 1 0 2
        // 1 0 2 2      the lone 1 at (0, 2) touches the first region only diagonally
        let map = ClassMap {
            width: 4,
            height: 3,
            classes: vec![1, 1, 0, 2, 0, 1, 0, 2, 1, 0, 2, 2],
        };
        let (mask, regions) = split(&map, 1);
        assert_eq!(mask, vec![1, 1, 0, 2, 0, 1, 0, 2, 3, 0, 2, 2]);
        let summary: Vec<(u16, u16, usize)> =
            regions.iter().map(|r| (r.id, r.class, r.pixels)).collect();
        assert_eq!(summary, vec![(1, 1, 3), (2, 2, 4), (3, 1, 1)]);
        let (mask, regions) = split(&map, 2);
        assert_eq!(mask, vec![1, 1, 0, 2, 0, 1, 0, 2, 0, 0, 2, 2]);
        assert_eq!(regions.len(), 2);
    }
}
