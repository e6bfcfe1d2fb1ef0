//! Broad phase: a uniform grid over axis-aligned boxes, built by counting sort in linear time
//! (the bucket sort of explicit codes, e.g. OpenRadioss TYPE7 or Benson & Hallquist 1990), so
//! that a query visits only the boxes near it instead of all of them.

use nalgebra::Vector3;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Corner with the smallest coordinates (m); `+inf` for the empty box.
    pub min: Vector3<f64>,
    /// Corner with the largest coordinates (m); `-inf` for the empty box.
    pub max: Vector3<f64>,
}

impl Aabb {
    /// The smallest box holding `points`.
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a Vector3<f64>>) -> Self {
        let mut b = Aabb {
            min: Vector3::repeat(f64::INFINITY),
            max: Vector3::repeat(f64::NEG_INFINITY),
        };
        for p in points {
            b.min = b.min.inf(p);
            b.max = b.max.sup(p);
        }
        b
    }

    /// The box grown by `margin` on every side (for example the largest distance a node moves
    /// in a step).
    pub fn grown(&self, margin: f64) -> Self {
        Aabb {
            min: self.min.add_scalar(-margin),
            max: self.max.add_scalar(margin),
        }
    }

    /// Whether `p` lies in the box, faces included.
    pub fn contains(&self, p: &Vector3<f64>) -> bool {
        (0..3).all(|a| self.min[a] <= p[a] && p[a] <= self.max[a])
    }

    /// Whether the two boxes share a point (touching counts).
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|a| self.min[a] <= other.max[a] && other.min[a] <= self.max[a])
    }

    /// The common part of two boxes (empty, `min > max` on some axis, when they do not
    /// overlap).
    pub fn intersection(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.sup(&other.min),
            max: self.max.inf(&other.max),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }
}

/// Boxes binned into the cells of a uniform grid they overlap.
#[derive(Debug, Clone)]
pub struct UniformGrid {
    origin: Vector3<f64>,
    inverse_cell: f64,
    dims: [usize; 3],
    /// Items of cell `k` are `items[cell_start[k]..cell_start[k + 1]]`, in ascending box id.
    cell_start: Vec<u32>,
    items: Vec<u32>,
    /// Number of boxes binned.
    boxes: usize,
}

impl UniformGrid {
    /// Bins `boxes` into cells of edge `cell` (a size near the typical box size keeps both the
    /// cells per box and the boxes per cell small). The number of cells is capped so a few huge
    /// boxes cannot make the grid explode.
    pub fn build(boxes: &[Aabb], cell: f64) -> Self {
        Self::build_with_limit(boxes, cell, 8)
    }

    /// [`Self::build`] with at most `cells_per_box` cells per box (8 there): a grid kept over
    /// many queries can afford more, finer cells than the bounds of a surface would get.
    pub fn build_with_limit(boxes: &[Aabb], cell: f64, cells_per_box: usize) -> Self {
        let bounds = boxes.iter().fold(
            Aabb {
                min: Vector3::repeat(f64::INFINITY),
                max: Vector3::repeat(f64::NEG_INFINITY),
            },
            |acc, b| acc.union(b),
        );
        if boxes.is_empty() {
            return Self {
                origin: Vector3::zeros(),
                inverse_cell: 1.0,
                dims: [1; 3],
                cell_start: vec![0, 0],
                items: Vec::new(),
                boxes: 0,
            };
        }
        let extent = bounds.max - bounds.min;
        let max_cells = (cells_per_box * boxes.len()).max(1) as f64;
        let mut cell = cell.max(1e-300);
        while (0..3)
            .map(|a| (extent[a] / cell).floor() + 1.0)
            .product::<f64>()
            > max_cells
        {
            cell *= 1.5;
        }
        let dims = [0, 1, 2].map(|a| (extent[a] / cell).floor() as usize + 1);
        let mut grid = Self {
            origin: bounds.min,
            inverse_cell: 1.0 / cell,
            dims,
            cell_start: Vec::new(),
            items: Vec::new(),
            boxes: boxes.len(),
        };
        let cells = dims[0] * dims[1] * dims[2];
        let mut count = vec![0u32; cells + 1];
        for b in boxes {
            grid.for_cells(b, |k| count[k + 1] += 1);
        }
        for k in 0..cells {
            count[k + 1] += count[k];
        }
        let mut next = count.clone();
        let mut items = vec![0u32; count[cells] as usize];
        for (i, b) in boxes.iter().enumerate() {
            grid.for_cells(b, |k| {
                items[next[k] as usize] = i as u32;
                next[k] += 1;
            });
        }
        grid.cell_start = count;
        grid.items = items;
        grid
    }

    fn cell_range(&self, b: &Aabb) -> Option<[std::ops::RangeInclusive<usize>; 3]> {
        let mut r = [0..=0, 0..=0, 0..=0];
        for a in 0..3 {
            let lo = floor((b.min[a] - self.origin[a]) * self.inverse_cell);
            let hi = floor((b.max[a] - self.origin[a]) * self.inverse_cell);
            let last = (self.dims[a] - 1) as f64;
            if hi < 0.0 || lo > last || lo.is_nan() || hi.is_nan() {
                return None;
            }
            r[a] = lo.max(0.0) as usize..=hi.min(last) as usize;
        }
        Some(r)
    }

    fn for_cells(&self, b: &Aabb, mut f: impl FnMut(usize)) {
        if let Some([rx, ry, rz]) = self.cell_range(b) {
            for k in rz {
                for j in ry.clone() {
                    for i in rx.clone() {
                        f(i + self.dims[0] * (j + self.dims[1] * k));
                    }
                }
            }
        }
    }

    /// The cell holding `p` as `[i, j, k]`, or `None` when `p` lies outside the grid's cells.
    fn cell_of(&self, p: &Vector3<f64>) -> Option<[usize; 3]> {
        let mut c = [0; 3];
        for a in 0..3 {
            let t = floor((p[a] - self.origin[a]) * self.inverse_cell);
            if !(t >= 0.0 && t <= (self.dims[a] - 1) as f64) {
                return None;
            }
            c[a] = t as usize;
        }
        Some(c)
    }

    /// The ids of the boxes binned into the cell holding `p` (ascending; every box containing
    /// `p` is among them), or `None` when `p` lies outside the grid's cells.
    pub fn items_at(&self, p: &Vector3<f64>) -> Option<&[u32]> {
        let [i, j, k] = self.cell_of(p)?;
        let c = i + self.dims[0] * (j + self.dims[1] * k);
        Some(&self.items[self.cell_start[c] as usize..self.cell_start[c + 1] as usize])
    }

    /// The id nearest to `p` by `distance` (lowest id among equals), `None` for an empty grid.
    /// `distance(i)` must be at least the distance from `p` to box `i`. The cells are searched
    /// in rings of growing Chebyshev distance `r` around the cell of `p`, until the best distance
    /// is within `r` cell edges (a box listed in no searched cell lies farther); a point outside
    /// the grid compares every box.
    pub fn nearest(&self, p: &Vector3<f64>, distance: impl Fn(u32) -> f64) -> Option<(u32, f64)> {
        let mut best = (u32::MAX, f64::INFINITY);
        let consider = |best: &mut (u32, f64), i: u32| {
            let d = distance(i);
            if d < best.1 || (d == best.1 && i < best.0) {
                *best = (i, d);
            }
        };
        let Some(c) = self.cell_of(p) else {
            (0..self.boxes as u32).for_each(|i| consider(&mut best, i));
            return (self.boxes > 0).then_some(best);
        };
        let edge = 1.0 / self.inverse_cell;
        for r in 0..=self.dims.into_iter().max().unwrap_or(1) {
            let lo = c.map(|x| x.saturating_sub(r));
            let hi = [0, 1, 2].map(|a| (c[a] + r).min(self.dims[a] - 1));
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        let ring = i.abs_diff(c[0]).max(j.abs_diff(c[1])).max(k.abs_diff(c[2]));
                        if ring == r {
                            let cell = i + self.dims[0] * (j + self.dims[1] * k);
                            let (a, b) = (self.cell_start[cell], self.cell_start[cell + 1]);
                            self.items[a as usize..b as usize]
                                .iter()
                                .for_each(|&e| consider(&mut best, e));
                        }
                    }
                }
            }
            if best.1 <= r as f64 * edge {
                break;
            }
        }
        (best.0 != u32::MAX).then_some(best)
    }

    /// Ids of the boxes sharing a cell with `query`, sorted and without repeats (a superset of
    /// the boxes that overlap it). `out` is cleared first.
    pub fn query(&self, query: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        self.for_cells(query, |k| {
            out.extend_from_slice(
                &self.items[self.cell_start[k] as usize..self.cell_start[k + 1] as usize],
            );
        });
        out.sort_unstable();
        out.dedup();
    }

    /// The ids of the entries `j` (positions in `items`) of the cells `query` meets for which
    /// `keep(j)` holds, marked in `marks` and read back in ascending order, without repeats: for
    /// a query that meets many cells (a slab across a whole body) this is linear in the ids
    /// found, where sorting them is not. `marks` is scratch space, all clear between calls.
    fn mark_cells(
        &self,
        query: &Aabb,
        marks: &mut Vec<u64>,
        out: &mut Vec<u32>,
        keep: impl Fn(usize) -> bool,
    ) {
        out.clear();
        marks.resize(marks.len().max(self.boxes.div_ceil(64)), 0);
        let mut any = false;
        self.for_cells(query, |k| {
            for j in self.cell_start[k] as usize..self.cell_start[k + 1] as usize {
                if keep(j) {
                    let i = self.items[j];
                    marks[(i / 64) as usize] |= 1u64 << (i % 64);
                    any = true;
                }
            }
        });
        if !any {
            return;
        }
        for (w, word) in marks.iter_mut().enumerate() {
            let mut bits = std::mem::take(word);
            while bits != 0 {
                out.push(64 * w as u32 + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
    }
}

/// A [`UniformGrid`] that keeps a copy of each box beside each of its entries in the cells, so a
/// query tests the boxes as it reads the cells, in memory order, instead of reading the box of
/// each id found at random. The grids detection keeps over a run hold tens of thousands of
/// boxes, and a slab across a body meets thousands whose cells it shares but few that it
/// overlaps: a random read each cost more than the test.
#[derive(Debug, Clone)]
pub struct BoxedGrid {
    grid: UniformGrid,
    /// `boxes[items[j]]` for every entry `j` of the grid's cells.
    entry_boxes: Vec<Aabb>,
}

impl BoxedGrid {
    /// [`UniformGrid::build_with_limit`], keeping the boxes.
    pub fn build_with_limit(boxes: &[Aabb], cell: f64, cells_per_box: usize) -> Self {
        let grid = UniformGrid::build_with_limit(boxes, cell, cells_per_box);
        let entry_boxes = grid.items.iter().map(|&i| boxes[i as usize]).collect();
        Self { grid, entry_boxes }
    }

    /// Ids of the boxes that overlap `query`, ascending, without repeats: those of the cells
    /// `query` meets whose box overlaps it. `marks` is scratch space, all clear between calls.
    pub fn query_overlapping(&self, query: &Aabb, marks: &mut Vec<u64>, out: &mut Vec<u32>) {
        self.grid
            .mark_cells(query, marks, out, |j| self.entry_boxes[j].overlaps(query));
    }
}

/// `v.floor()` without a call into libm (the baseline x86-64 target has no rounding
/// instruction): the integer part by conversion, one less for negative non-integers. Values of
/// magnitude `2^52` and more are integers already, as are infinities; NaN stays NaN. Equal to
/// `v.floor()` up to the sign of a zero result, which no cell index sees.
#[inline]
fn floor(v: f64) -> f64 {
    if v.abs() < 4_503_599_627_370_496.0 {
        let t = v as i64 as f64;
        if t > v {
            t - 1.0
        } else {
            t
        }
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    #[test]
    fn grid_queries_find_every_overlapping_box() {
        let mut rng = SplitMix64::new(4);
        let mut random_box = |size: f64| {
            let c = Vector3::new(
                rng.uniform(0.0, 10.0),
                rng.uniform(0.0, 5.0),
                rng.uniform(0.0, 2.0),
            );
            let h = Vector3::new(
                rng.uniform(0.0, size),
                rng.uniform(0.0, size),
                rng.uniform(0.0, size),
            );
            Aabb {
                min: c - h,
                max: c + h,
            }
        };
        let boxes: Vec<Aabb> = (0..2000).map(|_| random_box(0.3)).collect();
        let grid = UniformGrid::build(&boxes, 0.4);
        let mut found = Vec::new();
        for _ in 0..500 {
            let q = random_box(0.5);
            grid.query(&q, &mut found);
            for (i, b) in boxes.iter().enumerate() {
                if b.overlaps(&q) {
                    assert!(found.binary_search(&(i as u32)).is_ok(), "box {i} missed");
                }
            }
        }
    }

    /// `items_at` holds every box that contains the point, ascending; `nearest` finds the box
    /// nearest by a brute-force scan (distance to the box), inside and outside the grid.
    #[test]
    fn point_queries_match_brute_force_scans() {
        let mut rng = SplitMix64::new(11);
        let boxes: Vec<Aabb> = (0..1500)
            .map(|_| {
                let c = Vector3::new(
                    rng.uniform(0.0, 4.0),
                    rng.uniform(0.0, 3.0),
                    rng.uniform(0.0, 2.0),
                );
                let h = Vector3::repeat(rng.uniform(0.0, 0.2));
                Aabb {
                    min: c - h,
                    max: c + h,
                }
            })
            .collect();
        let grid = UniformGrid::build(&boxes, 0.25);
        let to_box = |b: &Aabb, p: &Vector3<f64>| (p - p.sup(&b.min).inf(&b.max)).norm();
        for _ in 0..400 {
            let p = Vector3::new(
                rng.uniform(-0.5, 4.5),
                rng.uniform(-0.5, 3.5),
                rng.uniform(-0.5, 2.5),
            );
            let holding: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].contains(&p))
                .collect();
            let at = grid.items_at(&p).unwrap_or(&[]);
            assert!(at.windows(2).all(|w| w[0] < w[1]), "not ascending");
            assert!(
                holding.iter().all(|i| at.binary_search(i).is_ok()),
                "{p:?}: {holding:?} not all in {at:?}"
            );
            let expected = (0..boxes.len() as u32)
                .map(|i| (i, to_box(&boxes[i as usize], &p)))
                .fold(
                    (u32::MAX, f64::INFINITY),
                    |b, (i, d)| if d < b.1 { (i, d) } else { b },
                );
            let found = grid
                .nearest(&p, |i| to_box(&boxes[i as usize], &p))
                .unwrap();
            assert_eq!(found, expected, "{p:?}");
        }
        assert_eq!(
            UniformGrid::build(&[], 1.0).nearest(&Vector3::zeros(), |_| 0.0),
            None
        );
    }

    #[test]
    fn a_boxed_grid_finds_exactly_the_overlapping_boxes() {
        let mut rng = SplitMix64::new(5);
        let mut random_box = |size: f64| {
            let c = Vector3::new(
                rng.uniform(0.0, 10.0),
                rng.uniform(0.0, 5.0),
                rng.uniform(0.0, 2.0),
            );
            let h = Vector3::repeat(rng.uniform(0.0, size));
            Aabb {
                min: c - h,
                max: c + h,
            }
        };
        let boxes: Vec<Aabb> = (0..2000).map(|_| random_box(0.3)).collect();
        let grid = BoxedGrid::build_with_limit(&boxes, 0.2, 64);
        let (mut marks, mut found) = (Vec::new(), Vec::new());
        for k in 0..500 {
            // Slabs across the boxes as well as small queries.
            let mut q = random_box(0.5);
            if k % 3 == 0 {
                q.min.y = -1.0;
                q.max.y = 6.0;
            }
            grid.query_overlapping(&q, &mut marks, &mut found);
            let expected: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].overlaps(&q))
                .collect();
            assert_eq!(found, expected);
            assert!(marks.iter().all(|&w| w == 0), "marks left set");
        }
    }

    #[test]
    fn floor_without_libm_is_floor() {
        let mut rng = SplitMix64::new(7);
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1e-300,
            2.5e15,
            -2.5e15 - 0.5,
            4503599627370495.5,
            -4503599627370495.5,
            4503599627370496.0,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        values.extend((0..10_000).map(|_| rng.uniform(-1e3, 1e3)));
        values.extend((0..10_000).map(|_| rng.uniform(-3.0, 3.0)));
        for v in values {
            assert_eq!(floor(v), v.floor(), "{v}");
        }
        assert!(floor(f64::NAN).is_nan());
    }
}
