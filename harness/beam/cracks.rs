//! Cracked zones of a beam, the failure-mode classification (FORMULATION 5, thesis 10.3) and the
//! bending-crack tip against time.
//!
//! An element is cracked when its crack indicator `eps_1 / eps_r` (largest principal
//! Green-Lagrange strain over `eps_r = w_cr / L`, thesis 5.1) is at least 1. The indicator is
//! history-free, so it is computed from any displacement (the final state or a snapshot).
//!
//! Geometry is read in the reference configuration, side view `x`-`y` (`x` along the beam, `y`
//! up): the beam's bounding box gives the bottom `y_b` and the height `h`; the load acts at
//! `x_load` (default: mid-span of the box) over `|x - x_load| <= a` (default `a = h / 4`, the
//! thesis hammer's half width); the supports are the body's constraints whose nodes all lie on the
//! bottom face; the cell size is `c = (6 V)^(1/3)` of the mean element volume `V` (six tetrahedra
//! per cube).

use std::collections::HashMap;

use impact_solver::model::Problem;
use impact_solver::Vector3;
use serde::{Deserialize, Serialize};

/// The beam a crack measure looks at (every field has a default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    /// The beam body.
    #[serde(default = "beam_body")]
    pub body: String,
    /// Position of the load along the beam (m); mid-span of the body's box by default.
    #[serde(default)]
    pub load_x: Option<f64>,
    /// Half width of the loaded strip (m); a quarter of the beam height by default.
    #[serde(default)]
    pub load_half_width: Option<f64>,
    /// Cracks (zone parts) of fewer elements are ignored.
    #[serde(default = "min_elements")]
    pub min_elements: usize,
}

fn beam_body() -> String {
    "beam".into()
}

fn min_elements() -> usize {
    12
}

impl Default for BeamSpec {
    fn default() -> Self {
        Self {
            body: beam_body(),
            load_x: None,
            load_half_width: None,
            min_elements: min_elements(),
        }
    }
}

/// Failure mode of a beam (thesis 10.3.2), with its code as a metric value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureMode {
    /// No qualifying crack (or only a bending crack below half the height): code 0.
    None,
    /// Mode I: only the bending crack: code 1.
    Bending,
    /// Bending crack and shear cracks: code 2.
    Mixed,
    /// Only shear cracks, or a bending crack below half the height: code 3.
    Shear,
}

impl FailureMode {
    /// The metric value: 0 none, 1 bending, 2 mixed, 3 shear.
    pub fn code(self) -> f64 {
        match self {
            FailureMode::None => 0.0,
            FailureMode::Bending => 1.0,
            FailureMode::Mixed => 2.0,
            FailureMode::Shear => 3.0,
        }
    }

    /// The mode of a metric value (`None` for anything that is not a code).
    pub fn from_code(code: f64) -> Option<FailureMode> {
        [
            FailureMode::None,
            FailureMode::Bending,
            FailureMode::Mixed,
            FailureMode::Shear,
        ]
        .into_iter()
        .find(|m| m.code() == code)
    }

    pub fn name(self) -> &'static str {
        match self {
            FailureMode::None => "none",
            FailureMode::Bending => "bending",
            FailureMode::Mixed => "mixed",
            FailureMode::Shear => "shear",
        }
    }
}

/// What a crack is taken for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrackKind {
    /// Rising from the bottom face within one beam height of the load, plane within 30 degrees
    /// of vertical (angle to the axis at least 60 degrees).
    Bending,
    /// Beside the loaded strip, plane inclined 25 to 65 degrees to the beam axis.
    Shear,
    /// Anything else (a vertical crack away from mid-span, a horizontal one, an inclined part
    /// under the load).
    Other,
}

/// Which side of the loaded strip a crack lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Left,
    Under,
    Right,
}

/// One crack: the part of a connected cracked zone on one side of (or under) the load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Crack {
    /// Index of the connected zone it belongs to.
    pub zone: usize,
    pub side: Side,
    pub kind: CrackKind,
    pub elements: usize,
    /// Mean `x` of its element centroids (m).
    pub x_center: f64,
    /// Angle of its plane (major principal axis of the centroids in the side view) to the beam
    /// axis, 0 to 90 degrees.
    pub angle_deg: f64,
    /// Extent of the centroids along that axis plus one cell (m).
    pub length: f64,
    /// Lowest and highest centroid above the bottom face (m): `top` is the height it reached.
    pub bottom: f64,
    pub top: f64,
    /// Whether it starts in the bottom layer of cells.
    pub from_bottom: bool,
}

/// The geometry the classification works in (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamFrame {
    pub x_load: f64,
    pub load_half_width: f64,
    pub y_bottom: f64,
    pub height: f64,
    /// Cell size (m).
    pub cell: f64,
    /// `[x_min, x_max]` of each support strip.
    pub supports: Vec<[f64; 2]>,
    pub min_elements: usize,
}

/// An element of the beam: reference centroid and nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamElement {
    pub centroid: Vector3<f64>,
    pub nodes: [u32; 4],
}

impl BeamFrame {
    /// The frame of `spec.body` in `problem`, with its elements (global ids `first..`).
    pub fn of(problem: &Problem, spec: &BeamSpec) -> Result<(BeamFrame, Vec<BeamElement>), String> {
        let model = &problem.model;
        let b = model
            .body_index(&spec.body)
            .ok_or_else(|| format!("no body named `{}`", spec.body))?;
        let body = &model.bodies[b];
        let (mut lo, mut hi) = (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        );
        for n in body.nodes.clone() {
            lo = lo.inf(&model.reference[n]);
            hi = hi.sup(&model.reference[n]);
        }
        let elements: Vec<BeamElement> = body
            .elements
            .clone()
            .map(|e| {
                let nodes = model.tets[e];
                BeamElement {
                    centroid: nodes
                        .iter()
                        .map(|&n| model.reference[n as usize])
                        .sum::<Vector3<f64>>()
                        / 4.0,
                    nodes,
                }
            })
            .collect();
        if elements.is_empty() {
            return Err(format!("body `{}` has no elements", spec.body));
        }
        let mean_volume =
            body.elements.clone().map(|e| model.volume[e]).sum::<f64>() / elements.len() as f64;
        let cell = (6.0 * mean_volume).cbrt();
        let height = hi.y - lo.y;
        let on_bottom = |n: u32| (model.reference[n as usize].y - lo.y).abs() <= 1e-6 * height;
        let supports = problem
            .constraints
            .iter()
            .filter(|c| {
                !c.nodes.is_empty()
                    && c.nodes
                        .iter()
                        .all(|&n| body.nodes.contains(&(n as usize)) && on_bottom(n))
            })
            .map(|c| {
                c.nodes
                    .iter()
                    .fold([f64::INFINITY, f64::NEG_INFINITY], |[a, z], &n| {
                        let x = model.reference[n as usize].x;
                        [a.min(x), z.max(x)]
                    })
            })
            .collect();
        Ok((
            BeamFrame {
                x_load: spec.load_x.unwrap_or(0.5 * (lo.x + hi.x)),
                load_half_width: spec.load_half_width.unwrap_or(0.25 * height),
                y_bottom: lo.y,
                height,
                cell,
                supports,
                min_elements: spec.min_elements,
            },
            elements,
        ))
    }

    /// Within one cell of the loaded strip and in the top two layers of cells.
    pub fn in_loading_region(&self, c: &Vector3<f64>) -> bool {
        (c.x - self.x_load).abs() <= self.load_half_width + self.cell
            && c.y >= self.y_bottom + self.height - 2.0 * self.cell
    }

    /// Within one cell of a support strip and in the bottom two layers of cells.
    pub fn in_support_region(&self, c: &Vector3<f64>) -> bool {
        c.y <= self.y_bottom + 2.0 * self.cell
            && self
                .supports
                .iter()
                .any(|[a, z]| c.x >= a - self.cell && c.x <= z + self.cell)
    }

    fn side(&self, c: &Vector3<f64>) -> Side {
        if c.x < self.x_load - self.load_half_width {
            Side::Left
        } else if c.x > self.x_load + self.load_half_width {
            Side::Right
        } else {
            Side::Under
        }
    }
}

/// Connected zones of the flagged elements: elements sharing a node (hence also those sharing
/// a face or an edge) are in the same zone. Zones and their elements come in ascending order.
pub fn zones(elements: &[BeamElement], flagged: &[bool]) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..elements.len()).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut owner: HashMap<u32, usize> = HashMap::new();
    for (e, el) in elements.iter().enumerate() {
        if !flagged[e] {
            continue;
        }
        for &n in &el.nodes {
            match owner.get(&n) {
                Some(&o) => {
                    let (a, b) = (find(&mut parent, o), find(&mut parent, e));
                    if a != b {
                        parent[a.max(b)] = a.min(b);
                    }
                }
                None => {
                    owner.insert(n, e);
                }
            }
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for e in (0..elements.len()).filter(|&e| flagged[e]) {
        let r = find(&mut parent, e);
        by_root.entry(r).or_default().push(e);
    }
    by_root.into_values().collect()
}

/// Angle of the major principal axis of the points (side view) to the `x` axis, 0 to 90
/// degrees, and the extent of the points along that axis.
fn principal_axis(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for (x, y) in points {
        sxx += (x - mx) * (x - mx);
        syy += (y - my) * (y - my);
        sxy += (x - mx) * (y - my);
    }
    // Major eigenvector of [[sxx, sxy], [sxy, syy]] at theta = atan2(2 sxy, sxx - syy) / 2.
    let theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (c, s) = (theta.cos(), theta.sin());
    let proj = points.iter().map(|(x, y)| x * c + y * s);
    let (lo, hi) = proj.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p), b.max(p))
    });
    (theta.abs().to_degrees().min(90.0), hi - lo)
}

/// The cracks of the flagged (cracked) elements and the failure mode they make.
///
/// 1. Connected zones ([`zones`]); each zone is cut into its parts left of, under and right of
///    the loaded strip `|x - x_load| <= a`, so that a bending crack at mid-span and the inclined
///    cracks branching from it are judged separately.
/// 2. A part is ignored when it has fewer than `min_elements` elements, or when every element
///    of it lies in the loading region (within one cell of the loaded strip, top two cell
///    layers) or a support region (within one cell of a support strip, bottom two layers):
///    local crushing and bearing, not cracks through the beam.
/// 3. Each remaining part gets its plane from the principal axes of its element centroids in
///    the side view (angle of the major axis to the beam axis).
/// 4. **Bending** crack: starts in the bottom layer of cells, its centre within one beam height
///    of `x_load`, plane at least 60 degrees to the axis (within 30 degrees of vertical).
///    **Shear** crack: left or right of the strip, plane 25 to 65 degrees to the axis.
///    Otherwise **other**.
/// 5. Mode: a bending crack counts when its top reaches half the height. `mixed` with a
///    counting bending crack and a shear crack, `bending` with only the first, `shear` with
///    only shear cracks (short bending cracks or not), `none` otherwise.
pub fn classify(
    frame: &BeamFrame,
    elements: &[BeamElement],
    cracked: &[bool],
) -> (FailureMode, Vec<Crack>) {
    let mut cracks = Vec::new();
    for (z, zone) in zones(elements, cracked).iter().enumerate() {
        for side in [Side::Left, Side::Under, Side::Right] {
            let part: Vec<&Vector3<f64>> = zone
                .iter()
                .map(|&e| &elements[e].centroid)
                .filter(|c| frame.side(c) == side)
                .collect();
            if part.len() < frame.min_elements
                || part
                    .iter()
                    .all(|c| frame.in_loading_region(c) || frame.in_support_region(c))
            {
                continue;
            }
            let points: Vec<(f64, f64)> = part.iter().map(|c| (c.x, c.y)).collect();
            let (angle_deg, extent) = principal_axis(&points);
            let x_center = points.iter().map(|p| p.0).sum::<f64>() / points.len() as f64;
            let (bottom, top) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                    (a.0.min(p.1 - frame.y_bottom), a.1.max(p.1 - frame.y_bottom))
                });
            let from_bottom = bottom < frame.cell;
            let kind = if from_bottom
                && (x_center - frame.x_load).abs() <= frame.height
                && angle_deg >= 60.0
            {
                CrackKind::Bending
            } else if side != Side::Under && (25.0..=65.0).contains(&angle_deg) {
                CrackKind::Shear
            } else {
                CrackKind::Other
            };
            cracks.push(Crack {
                zone: z,
                side,
                kind,
                elements: part.len(),
                x_center,
                angle_deg,
                length: extent + frame.cell,
                bottom,
                top,
                from_bottom,
            });
        }
    }
    let bending = cracks
        .iter()
        .any(|c| c.kind == CrackKind::Bending && c.top >= 0.5 * frame.height);
    let shear = cracks.iter().any(|c| c.kind == CrackKind::Shear);
    let mode = match (bending, shear) {
        (true, true) => FailureMode::Mixed,
        (true, false) => FailureMode::Bending,
        (false, true) => FailureMode::Shear,
        (false, false) => FailureMode::None,
    };
    (mode, cracks)
}

/// The crack indicator of every element of the beam at displacement `u`, flagged at 1.
fn cracked_at(problem: &Problem, spec: &BeamSpec, u: &[Vector3<f64>]) -> Result<Vec<bool>, String> {
    let b = problem
        .model
        .body_index(&spec.body)
        .ok_or_else(|| format!("no body named `{}`", spec.body))?;
    let range = problem.model.bodies[b].elements.clone();
    let indicator = problem.model.element_fields(u).crack_indicator;
    Ok(indicator[range].iter().map(|&i| i >= 1.0).collect())
}

/// The failure mode and the cracks of the beam at displacement `u` (see [`classify`]).
pub fn failure_mode_at(
    problem: &Problem,
    spec: &BeamSpec,
    u: &[Vector3<f64>],
) -> Result<(FailureMode, Vec<Crack>, BeamFrame), String> {
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    let cracked = cracked_at(problem, spec, u)?;
    let (mode, cracks) = classify(&frame, &elements, &cracked);
    Ok((mode, cracks, frame))
}

/// The mode by name and the table of cracks, for the report.
pub fn failure_mode_details(mode: FailureMode, cracks: &[Crack], frame: &BeamFrame) -> String {
    let mut s = format!(
        "mode: {} (load at x = {:.3} m, strip half width {:.3} m, height {:.3} m, cell {:.4} m)\n",
        mode.name(),
        frame.x_load,
        frame.load_half_width,
        frame.height,
        frame.cell
    );
    s.push_str("zone | side | kind | elements | x centre (m) | angle (deg) | length (m) | bottom (m) | height reached (m)\n");
    for c in cracks {
        s.push_str(&format!(
            "{} | {:?} | {:?} | {} | {:.3} | {:.1} | {:.3} | {:.3} | {:.3}\n",
            c.zone, c.side, c.kind, c.elements, c.x_center, c.angle_deg, c.length, c.bottom, c.top
        ));
    }
    s
}

/// Snapshots on each side of a snapshot used for the tip speed (a 5-snapshot central
/// difference).
pub const TIP_SPEED_HALF_WINDOW: usize = 2;

/// Height of the bending-crack tip from one state's flags: the highest centroid (above the
/// bottom face) of the cracked elements within one cell of the loaded strip
/// (`|x - x_load| <= a + c`), outside the loading region, connected (by shared nodes, through
/// such elements) to an element of the bottom layer of cells; 0 when there is none.
pub fn tip_height(frame: &BeamFrame, elements: &[BeamElement], cracked: &[bool]) -> f64 {
    let near: Vec<bool> = elements
        .iter()
        .zip(cracked)
        .map(|(e, &f)| {
            f && (e.centroid.x - frame.x_load).abs() <= frame.load_half_width + frame.cell
                && !frame.in_loading_region(&e.centroid)
        })
        .collect();
    zones(elements, &near)
        .iter()
        .filter(|z| {
            z.iter()
                .any(|&e| elements[e].centroid.y - frame.y_bottom < frame.cell)
        })
        .flat_map(|z| z.iter().map(|&e| elements[e].centroid.y - frame.y_bottom))
        .fold(0.0, f64::max)
}

/// `(t, height, speed)` from tip heights at times: `height` is the highest the tip has reached
/// so far (the running maximum, so that a crack closing elastically does not count as a tip
/// moving back), `speed = (h_{i+k} - h_{i-k}) / (t_{i+k} - t_{i-k})` with
/// `k = TIP_SPEED_HALF_WINDOW`, the window shrinking to one side at the ends.
pub fn tip_speeds(times: &[f64], heights: &[f64]) -> Vec<(f64, f64, f64)> {
    let mut reached = Vec::with_capacity(heights.len());
    let mut best: f64 = 0.0;
    for h in heights {
        best = best.max(*h);
        reached.push(best);
    }
    let n = times.len();
    (0..n)
        .map(|i| {
            let (a, b) = (
                i.saturating_sub(TIP_SPEED_HALF_WINDOW),
                (i + TIP_SPEED_HALF_WINDOW).min(n - 1),
            );
            let speed = if b > a && times[b] > times[a] {
                (reached[b] - reached[a]) / (times[b] - times[a])
            } else {
                0.0
            };
            (times[i], reached[i], speed)
        })
        .collect()
}

/// The bending-crack tip over the snapshots of a run: `(t, height reached (m), speed (m/s))`
/// (see [`tip_height`] and [`tip_speeds`]).
pub fn crack_tip_history(
    problem: &Problem,
    snapshots: &[impact_solver::dynamics::Snapshot],
    spec: &BeamSpec,
) -> Result<Vec<(f64, f64, f64)>, String> {
    let (frame, elements) = BeamFrame::of(problem, spec)?;
    let mut times = Vec::with_capacity(snapshots.len());
    let mut heights = Vec::with_capacity(snapshots.len());
    for s in snapshots {
        let cracked = cracked_at(problem, spec, &s.u)?;
        times.push(s.time);
        heights.push(tip_height(&frame, &elements, &cracked));
    }
    Ok(tip_speeds(&times, &heights))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A side-view grid of `nx x ny` unit-less cells of size `c`, one element per cell whose
    /// nodes are the cell's corners (as a tetrahedron would share them), `nz = 1`.
    fn grid(nx: usize, ny: usize, c: f64) -> Vec<BeamElement> {
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let mut out = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                out.push(BeamElement {
                    centroid: Vector3::new((i as f64 + 0.5) * c, (j as f64 + 0.5) * c, 0.0),
                    nodes: [id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)],
                });
            }
        }
        out
    }

    /// Beam 3.0 x 0.6 in cells of 0.05 (60 x 12), load at 1.5, supports at 0.1 and 2.9.
    fn frame() -> BeamFrame {
        BeamFrame {
            x_load: 1.5,
            load_half_width: 0.15,
            y_bottom: 0.0,
            height: 0.6,
            cell: 0.05,
            supports: vec![[0.05, 0.15], [2.85, 2.95]],
            min_elements: 4,
        }
    }

    fn flag(elements: &[BeamElement], cells: &[(usize, usize)]) -> Vec<bool> {
        let mut f = vec![false; elements.len()];
        for &(i, j) in cells {
            f[j * 60 + i] = true;
        }
        f
    }

    /// A vertical crack at mid-span, from the bottom up to row `rows - 1`.
    fn vertical(rows: usize) -> Vec<(usize, usize)> {
        (0..rows).map(|j| (29, j)).collect()
    }

    /// A 45-degree crack on the left rising towards the load: columns 16..24 over rows 0..8.
    fn shear_left() -> Vec<(usize, usize)> {
        (0..8).map(|k| (16 + k, k)).collect()
    }

    #[test]
    fn vertical_mid_span_crack_is_bending() {
        let e = grid(60, 12, 0.05);
        let (mode, cracks) = classify(&frame(), &e, &flag(&e, &vertical(9)));
        assert_eq!(mode, FailureMode::Bending);
        assert_eq!(cracks.len(), 1);
        let c = &cracks[0];
        assert_eq!(c.kind, CrackKind::Bending);
        assert!((c.angle_deg - 90.0).abs() < 1e-9);
        assert!((c.top - 0.425).abs() < 1e-12);
        assert!((c.length - 0.45).abs() < 1e-12);
        assert!(c.from_bottom);
    }

    #[test]
    fn bending_plus_inclined_cracks_is_mixed() {
        let e = grid(60, 12, 0.05);
        let mut cells = vertical(9);
        cells.extend(shear_left());
        // Mirror image on the right: columns 43..35 over rows 0..8.
        cells.extend((0..8).map(|k| (43 - k, k)));
        let (mode, cracks) = classify(&frame(), &e, &flag(&e, &cells));
        assert_eq!(mode, FailureMode::Mixed);
        let shear: Vec<&Crack> = cracks
            .iter()
            .filter(|c| c.kind == CrackKind::Shear)
            .collect();
        assert_eq!(shear.len(), 2);
        for c in shear {
            assert!((c.angle_deg - 45.0).abs() < 1e-9, "{c:?}");
            assert!((c.length - (2.0f64.sqrt() * 0.35 + 0.05)).abs() < 1e-12);
        }
    }

    #[test]
    fn only_inclined_cracks_or_a_short_bending_crack_is_shear() {
        let e = grid(60, 12, 0.05);
        let (mode, _) = classify(&frame(), &e, &flag(&e, &shear_left()));
        assert_eq!(mode, FailureMode::Shear);
        // A bending crack below half the height does not count.
        let mut cells = vertical(5);
        cells.extend(shear_left());
        let (mode, cracks) = classify(&frame(), &e, &flag(&e, &cells));
        assert_eq!(mode, FailureMode::Shear);
        assert!(cracks
            .iter()
            .any(|c| c.kind == CrackKind::Bending && c.top < 0.3));
        // ... and alone it is no failure mode at all.
        let (mode, _) = classify(&frame(), &e, &flag(&e, &vertical(5)));
        assert_eq!(mode, FailureMode::None);
    }

    #[test]
    fn a_bending_crack_branching_into_inclined_arms_is_cut_at_the_strip() {
        // One connected zone: vertical at column 29 up to row 7, and an arm at 45 degrees from
        // row 6 down to the bottom on the left (columns 27..32 are under the strip).
        let e = grid(60, 12, 0.05);
        let cells: Vec<(usize, usize)> = vertical(8)
            .into_iter()
            .chain((0..7).map(|k| (28 - k, 6 - k)))
            .collect();
        let flags = flag(&e, &cells);
        assert_eq!(zones(&e, &flags).len(), 1);
        let (_, cracks) = classify(&frame(), &e, &flags);
        assert!(cracks
            .iter()
            .any(|c| c.side == Side::Under && c.kind == CrackKind::Bending));
        assert!(cracks
            .iter()
            .any(|c| c.side == Side::Left && c.kind == CrackKind::Shear));
    }

    #[test]
    fn small_zones_and_bearing_zones_are_ignored() {
        let e = grid(60, 12, 0.05);
        // Three cracked cells: below min_elements. A crushed patch under the load (top two
        // rows) and a bearing patch over a support (bottom two rows).
        let mut cells = vec![(10, 5), (10, 6), (10, 7)];
        cells.extend((27..33).flat_map(|i| [(i, 10), (i, 11)]));
        cells.extend((0..4).flat_map(|i| [(i, 0), (i, 1)]));
        let (mode, cracks) = classify(&frame(), &e, &flag(&e, &cells));
        assert_eq!(mode, FailureMode::None);
        assert!(cracks.is_empty(), "{cracks:?}");
    }

    #[test]
    fn codes_round_trip() {
        for m in [
            FailureMode::None,
            FailureMode::Bending,
            FailureMode::Mixed,
            FailureMode::Shear,
        ] {
            assert_eq!(FailureMode::from_code(m.code()), Some(m));
        }
        assert_eq!(FailureMode::from_code(1.5), None);
    }

    #[test]
    fn tip_follows_the_mid_span_zone_connected_to_the_bottom() {
        let e = grid(60, 12, 0.05);
        let f = frame();
        assert_eq!(tip_height(&f, &e, &vec![false; e.len()]), 0.0);
        assert!((tip_height(&f, &e, &flag(&e, &vertical(6))) - 0.275).abs() < 1e-12);
        // A cracked patch in the middle of the height, not connected to the bottom, and a
        // crack at the bottom far from mid-span do not count.
        let mut cells = vertical(3);
        cells.extend([(29, 6), (29, 7), (10, 0), (10, 1), (10, 2), (10, 3)]);
        assert!((tip_height(&f, &e, &flag(&e, &cells)) - 0.125).abs() < 1e-12);
    }

    #[test]
    fn tip_speed_from_a_steady_crack_and_a_closing_one() {
        // Tip rising at 1000 m/s, sampled every 20 us: every window gives 1000 m/s.
        let t: Vec<f64> = (0..10).map(|i| i as f64 * 2e-5).collect();
        let h: Vec<f64> = t.iter().map(|t| 1000.0 * t).collect();
        for (_, _, v) in tip_speeds(&t, &h) {
            assert!((v - 1000.0).abs() < 1e-6);
        }
        // A crack that reaches 0.3 m then closes: the height reached stays 0.3, speed 0.
        let h = [0.0, 0.1, 0.2, 0.3, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        let s = tip_speeds(&t, &h);
        assert!(s[4..].iter().all(|&(_, h, _)| h == 0.3));
        assert_eq!(s[9].2, 0.0);
        // Central 5-point difference at i = 2: (0.3 - 0.0) / 80 us.
        assert!((s[2].2 - 0.3 / 8e-5).abs() < 1e-6);
    }
}

/// Runs a beam drop case and prints its crack table and tip history (about 30 s per case):
/// `BEAM_CASE=drop-2ms cargo test --release -p impact-vv --lib -- --ignored print_beam_case`.
#[cfg(test)]
mod case_run {
    use super::*;

    #[test]
    #[ignore]
    fn print_beam_case() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let name = std::env::var("BEAM_CASE").unwrap_or_else(|_| "drop-2ms".into());
        let case =
            crate::case_file::load_spec(&root.join("cases/beam").join(format!("{name}.yaml")))
                .unwrap();
        let scene = case.scene.clone().unwrap();
        // The microplane file is named relative to the case's folder.
        std::env::set_current_dir(root.join("cases/beam")).unwrap();
        let mut problem = impact_solver::scene::build_problem(&scene).unwrap();
        let options = crate::execute::ExecuteOptions {
            out: None,
            stem: "run",
            fields: false,
            time_limit_s: None,
            stop: None,
        };
        let run =
            crate::execute::execute(&mut problem, &scene.analysis, &options, &mut |_| {}).unwrap();
        let spec = BeamSpec::default();
        let (mode, cracks, frame) = failure_mode_at(&problem, &spec, &run.u).unwrap();
        println!("{}", failure_mode_details(mode, &cracks, &frame));
        for (t, h, v) in crack_tip_history(&problem, run.snapshots(), &spec).unwrap() {
            println!("tip {:.3} ms {:.3} m {:.0} m/s", t * 1e3, h, v);
        }
    }
}
