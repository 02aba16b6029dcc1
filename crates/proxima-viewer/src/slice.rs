//! The signed-distance slice: a plane through the mesh's grown bounding box,
//! sampled at cell centres, coloured by a diverging map (blue inside, red
//! outside, white on the surface) with its zero contour, and the signed
//! distance at the query point. Computed on worker threads by the app; no
//! GL, no egui: unit-tested against the library's own `signed_distance`.

use crate::scene::{Overlay, SliceImage, colors, next_id};
use crate::settings::{Axis, SLICE_MARGIN};
use proxima::prelude::*;
use proxima::sdf::{SdfConfig, Sign, SignedDistance, SignedDistanceField};
use std::sync::Arc;
use std::time::Instant;

/// Samples along the longer side of a slice (the shorter side gets as many
/// as keep the cells square). Fixed, so the work per slice is bounded: at
/// most 128² signed distances.
pub const SLICE_RESOLUTION: usize = 128;

/// The signed distance field of `mesh` with the side decided by `sign` (the
/// library's defaults otherwise). The error is one line.
///
/// ```
/// use proxima::Sign;
/// use proxima_viewer::slice::signed_distance_field;
/// let sphere = proxima::mesh::generate::noisy_icosphere(4, 1);
/// let field = signed_distance_field(&sphere, Sign::Pseudonormal).unwrap();
/// assert_eq!(field.sign(), Sign::Pseudonormal);
/// ```
pub fn signed_distance_field(mesh: &Mesh, sign: Sign) -> Result<Arc<SignedDistanceField>, String> {
    let config = SdfConfig {
        sign,
        ..SdfConfig::default()
    };
    SignedDistanceField::new(mesh, &config)
        .map(Arc::new)
        .map_err(|e| e.to_string())
}

/// `bounds` grown by [`SLICE_MARGIN`] of its size on every side: what a
/// slice covers.
pub fn grown_box(bounds: &Aabb) -> Aabb {
    let grow = SLICE_MARGIN * bounds.size();
    Aabb::new(bounds.min - grow, bounds.max + grow)
}

/// The name of a sign method as the panel and the CLI spell it.
pub fn sign_name(sign: Sign) -> &'static str {
    match sign {
        Sign::WindingNumber => "winding number",
        Sign::Pseudonormal => "pseudonormal",
    }
}

/// A rectangle of sample points in the plane `axis = position`, covering the
/// bounding box grown by [`SLICE_MARGIN`] on every side. Its two in-plane
/// axes are `u = axis + 1` and `v = axis + 2` (mod 3), so that `u × v` is the
/// plane's normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlicePlane {
    /// The plane's normal.
    pub axis: Axis,
    /// The plane's coordinate along `axis`.
    pub position: f32,
    /// The rectangle's smallest corner (`u`, `v`).
    pub min: [f32; 2],
    /// Cell size along `u` and `v`.
    pub cell: [f32; 2],
    /// Cells along `u` and `v`.
    pub resolution: [usize; 2],
}

impl SlicePlane {
    /// The plane `axis = position` over `bounds` grown by [`SLICE_MARGIN`],
    /// `resolution` cells along its longer side. Fails on an empty or
    /// infinite box, a position that is not finite or a zero resolution.
    ///
    /// ```
    /// use proxima::{Aabb, Vec3};
    /// use proxima_viewer::settings::Axis;
    /// use proxima_viewer::slice::SlicePlane;
    /// let bounds = Aabb::new(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0));
    /// let plane = SlicePlane::through(&bounds, Axis::Z, 0.5, 8).unwrap();
    /// assert_eq!(plane.resolution, [8, 4]); // square cells, x longer than y
    /// assert_eq!(plane.point(0, 0).z, 0.5);
    /// ```
    pub fn through(bounds: &Aabb, axis: Axis, position: f32, resolution: usize) -> Result<Self, String> {
        if bounds.is_empty() || !bounds.is_finite() {
            return Err("the slice needs a finite, non-empty bounding box".into());
        }
        if !position.is_finite() {
            return Err(format!("the slice position must be finite, got {position}"));
        }
        if resolution == 0 {
            return Err("the slice resolution must be at least 1".into());
        }
        let (u, v) = Self::plane_axes(axis);
        let grown = grown_box(bounds);
        let size = [grown.size()[u], grown.size()[v]];
        let longest = size[0].max(size[1]);
        let count = |s: f32| {
            if longest > 0.0 {
                ((resolution as f32 * s / longest).round() as usize).clamp(1, resolution)
            } else {
                resolution
            }
        };
        let resolution = [count(size[0]), count(size[1])];
        // A flat box (a planar mesh seen edge-on) still gets cells of some size.
        let fallback = longest.max(1e-6) / resolution[0].max(resolution[1]) as f32;
        let cell = std::array::from_fn(|k| {
            if size[k] > 0.0 {
                size[k] / resolution[k] as f32
            } else {
                fallback
            }
        });
        Ok(Self {
            axis,
            position,
            min: [grown.min[u], grown.min[v]],
            cell,
            resolution,
        })
    }

    /// The in-plane coordinate axes `(u, v)` of a slice normal to `axis`.
    pub fn plane_axes(axis: Axis) -> (usize, usize) {
        let a = axis.index();
        ((a + 1) % 3, (a + 2) % 3)
    }

    /// The point at in-plane coordinates `(u, v)`.
    fn at(&self, u: f32, v: f32) -> Vec3 {
        let (ua, va) = Self::plane_axes(self.axis);
        let mut p = Vec3::ZERO;
        p[self.axis.index()] = self.position;
        p[ua] = u;
        p[va] = v;
        p
    }

    /// The centre of cell `(i, j)` (`i` along `u`).
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        self.at(
            self.min[0] + (i as f32 + 0.5) * self.cell[0],
            self.min[1] + (j as f32 + 0.5) * self.cell[1],
        )
    }

    /// Every cell centre, `i` fastest.
    pub fn points(&self) -> Vec<Vec3> {
        let [nu, nv] = self.resolution;
        (0..nv).flat_map(|j| (0..nu).map(move |i| self.point(i, j))).collect()
    }

    /// The rectangle's corners: `min`, `+u`, `+u +v`, `+v`.
    pub fn corners(&self) -> [Vec3; 4] {
        let u1 = self.min[0] + self.cell[0] * self.resolution[0] as f32;
        let v1 = self.min[1] + self.cell[1] * self.resolution[1] as f32;
        [
            self.at(self.min[0], self.min[1]),
            self.at(u1, self.min[1]),
            self.at(u1, v1),
            self.at(self.min[0], v1),
        ]
    }
}

/// The signed distances on a slice, its picture and its zero contour.
#[derive(Clone, Debug)]
pub struct SdfSlice {
    /// Where the values are.
    pub plane: SlicePlane,
    /// How the side was decided.
    pub sign: Sign,
    /// Signed distance at each cell centre, `i` fastest (NaN where the
    /// library has no answer).
    pub values: Vec<f32>,
    /// The largest |value| (1 when every value is 0 or NaN): the colour map's scale.
    pub max_abs: f32,
    /// Cells whose centre is inside (negative value).
    pub inside: usize,
    /// Seconds the signed distances took.
    pub seconds: f64,
    /// The coloured texture over the plane's rectangle.
    pub image: Arc<SliceImage>,
    /// Segments where the sign changes, on the plane.
    pub contour: Vec<[Vec3; 2]>,
}

impl SdfSlice {
    /// Evaluates `field` on `plane` (all cores), colours it and traces its
    /// zero contour.
    pub fn compute(field: &SignedDistanceField, plane: SlicePlane) -> Self {
        let points = plane.points();
        let start = Instant::now();
        let values: Vec<f32> = field
            .signed_distance_batch(&points)
            .into_iter()
            .map(|d| d.map_or(f32::NAN, |d| d.distance))
            .collect();
        let seconds = start.elapsed().as_secs_f64();
        let max_abs = values
            .iter()
            .filter(|v| v.is_finite())
            .fold(0f32, |m, v| m.max(v.abs()));
        let max_abs = if max_abs > 0.0 { max_abs } else { 1.0 };
        let image = Arc::new(SliceImage {
            id: next_id(),
            size: plane.resolution,
            pixels: values.iter().map(|&d| diverging_color(d, max_abs)).collect(),
            corners: plane.corners(),
        });
        Self {
            inside: values.iter().filter(|&&d| d < 0.0).count(),
            contour: zero_contour(&plane, &values),
            plane,
            sign: field.sign(),
            values,
            max_abs,
            seconds,
            image,
        }
    }

    /// The zero contour as overlay lines.
    pub fn contour_overlay(&self) -> Overlay {
        let mut overlay = Overlay::default();
        for [a, b] in &self.contour {
            overlay.line(*a, *b, colors::ZERO_CONTOUR);
        }
        overlay
    }
}

/// The diverging colour of signed distance `d` on a scale of `max_abs`:
/// white at 0, towards [`colors::SLICE_INSIDE`] (blue) for negative values
/// and [`colors::SLICE_OUTSIDE`] (red) for positive ones, by the square root
/// of `|d| / max_abs`, reaching them at `|d| = max_abs`. The square root
/// because a slice through the grown box is mostly outside: its largest
/// distances are in the corners, several times the deepest inside, and a
/// linear ramp would leave the inside nearly white. Grey for a value that is
/// not a number.
///
/// ```
/// use proxima_viewer::scene::colors;
/// use proxima_viewer::slice::diverging_color;
/// assert_eq!(diverging_color(0.0, 2.0), colors::SLICE_ZERO);
/// assert_eq!(diverging_color(-2.0, 2.0), colors::SLICE_INSIDE);
/// assert_eq!(diverging_color(5.0, 2.0), colors::SLICE_OUTSIDE); // clamped
/// ```
pub fn diverging_color(d: f32, max_abs: f32) -> [u8; 4] {
    if d.is_nan() {
        return [128, 128, 128, 255];
    }
    let t = if max_abs > 0.0 {
        (d.abs() / max_abs).min(1.0).sqrt()
    } else {
        1.0
    };
    let end = if d < 0.0 {
        colors::SLICE_INSIDE
    } else {
        colors::SLICE_OUTSIDE
    };
    let white = colors::SLICE_ZERO;
    std::array::from_fn(|k| (white[k] as f32 + t * (end[k] as f32 - white[k] as f32)).round() as u8)
}

/// The segments where the sign of `values` (on `plane`'s cell centres, `i`
/// fastest) changes between neighbouring cells, by marching squares: each
/// square of four neighbouring centres with both signs gets one or two
/// segments between the points where the values interpolate linearly to 0.
/// Negative counts as inside, zero and positive as outside; squares with a
/// NaN are skipped. (The sign can also jump without passing through zero,
/// where a method decides the side differently on the two sides of a hole:
/// the line then marks that jump.)
pub fn zero_contour(plane: &SlicePlane, values: &[f32]) -> Vec<[Vec3; 2]> {
    let [nu, nv] = plane.resolution;
    let mut out = Vec::new();
    if values.len() != nu * nv {
        return out;
    }
    let value = |i: usize, j: usize| values[i + nu * j];
    for j in 0..nv.saturating_sub(1) {
        for i in 0..nu.saturating_sub(1) {
            // Corners counter-clockwise from (i, j); edge e joins corner e and e + 1.
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let d = corners.map(|(a, b)| value(a, b));
            if d.iter().any(|x| x.is_nan()) {
                continue;
            }
            let inside = d.map(|x| x < 0.0);
            let case = inside
                .iter()
                .enumerate()
                .fold(0usize, |c, (k, &b)| c | ((b as usize) << k));
            if case == 0 || case == 15 {
                continue;
            }
            let crossing = |e: usize| {
                let (k0, k1) = (e, (e + 1) % 4);
                let (p0, p1) = (
                    plane.point(corners[k0].0, corners[k0].1),
                    plane.point(corners[k1].0, corners[k1].1),
                );
                let t = d[k0] / (d[k0] - d[k1]);
                let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.5 };
                p0 + t * (p1 - p0)
            };
            let changed: Vec<usize> = (0..4).filter(|&e| inside[e] != inside[(e + 1) % 4]).collect();
            match changed.len() {
                2 => out.push([crossing(changed[0]), crossing(changed[1])]),
                4 => {
                    // A saddle: the centre's sign (the mean) decides which
                    // diagonal is connected. The two corners of the other
                    // sign are cut off, each by the segment between its two
                    // edges: corners 1 and 3 (edges 0-1 and 2-3) when corner
                    // 0 is on the centre's side, else corners 0 and 2.
                    let centre_inside = d.iter().sum::<f32>() < 0.0;
                    let start = if inside[0] == centre_inside { 0 } else { 1 };
                    out.push([crossing(start), crossing(start + 1)]);
                    out.push([crossing(start + 2), crossing((start + 3) % 4)]);
                }
                _ => {}
            }
        }
    }
    out
}

/// The query point's signed distance and winding number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdfReadout {
    /// The signed distance by the chosen sign method (`None`: no answer).
    pub signed_distance: Option<SignedDistance>,
    /// How its side was decided.
    pub sign: Sign,
    /// The winding number at the point.
    pub winding_number: f32,
}

impl SdfReadout {
    /// The readout at `p`: the signed distance by `field`, the winding number
    /// by `winding` (a field whose sign is the winding number; it may be
    /// `field` itself).
    pub fn at(field: &SignedDistanceField, winding: &SignedDistanceField, p: Vec3) -> Self {
        let signed_distance = field.signed_distance(p);
        let winding_number = match signed_distance.and_then(|d| d.winding_number) {
            Some(w) => w,
            None => winding.winding_number(p),
        };
        Self {
            signed_distance,
            sign: field.sign(),
            winding_number,
        }
    }

    /// Inside by the chosen sign method (`None` without an answer).
    pub fn inside(&self) -> Option<bool> {
        self.signed_distance.map(|d| d.is_inside())
    }

    /// `true` when the winding number's side differs from the chosen method's.
    pub fn methods_disagree(&self) -> bool {
        self.inside()
            .is_some_and(|inside| inside != (self.winding_number > 0.5))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proxima::mesh::generate::noisy_icosphere;

    #[test]
    fn slice_values_are_the_library_signed_distances_at_the_cell_centres() {
        let sphere = noisy_icosphere(6, 3);
        for sign in [Sign::WindingNumber, Sign::Pseudonormal] {
            let field = signed_distance_field(&sphere, sign).unwrap();
            for (axis, position) in [(Axis::Z, 0.1), (Axis::X, -0.4), (Axis::Y, 0.95)] {
                let plane = SlicePlane::through(&field.bounds(), axis, position, 24).unwrap();
                let slice = SdfSlice::compute(&field, plane);
                assert_eq!(slice.values.len(), plane.resolution[0] * plane.resolution[1]);
                assert_eq!(slice.sign, sign);
                let [nu, nv] = plane.resolution;
                for j in 0..nv {
                    for i in 0..nu {
                        let p = plane.point(i, j);
                        assert_eq!(p[axis.index()], position);
                        let expected = field.signed_distance(p).unwrap().distance;
                        assert_eq!(slice.values[i + nu * j], expected, "{sign:?} {axis:?} {i} {j}");
                    }
                }
                let inside = slice.values.iter().filter(|&&d| d < 0.0).count();
                assert_eq!(slice.inside, inside);
                assert_eq!(slice.image.pixels.len(), slice.values.len());
                assert_eq!(slice.image.corners, plane.corners());
            }
        }
    }

    #[test]
    fn a_slice_through_a_sphere_is_inside_near_the_centre_only() {
        // The exact winding number (every triangle summed in f64), so this
        // checks the slice and its contour, not the tree's accuracy. The
        // middle of a sphere of radius about 1 is inside by about 1, the
        // corners outside.
        let config = SdfConfig {
            exact: true,
            ..SdfConfig::default()
        };
        let field = SignedDistanceField::new(&noisy_icosphere(8, 1), &config).unwrap();
        let plane = SlicePlane::through(&field.bounds(), Axis::Z, 0.0, 33).unwrap();
        let slice = SdfSlice::compute(&field, plane);
        let [nu, nv] = plane.resolution;
        let middle = slice.values[nu / 2 + nu * (nv / 2)];
        assert!((-1.5..-0.3).contains(&middle), "{middle}");
        assert!(slice.values[0] > 0.0 && slice.values[nu * nv - 1] > 0.0);
        assert!(slice.inside > 0 && slice.inside < nu * nv);
        assert!(slice.max_abs >= -middle);
        // The contour lies on the surface, within a cell of it (a closed
        // sphere: the sign changes only there).
        assert!(slice.contour.len() > 20);
        let cell = Vec3::new(plane.cell[0], plane.cell[1], 0.0).length();
        for [a, b] in &slice.contour {
            for p in [a, b] {
                assert_eq!(p.z, 0.0);
                let d = field.signed_distance(*p).unwrap().distance.abs();
                assert!(d <= cell, "{p}: {d} from the surface, cells of {cell}");
            }
        }
        assert_eq!(slice.contour_overlay().lines.len(), 2 * slice.contour.len());
    }

    #[test]
    fn the_colour_map_is_white_at_zero_and_monotone() {
        assert_eq!(diverging_color(0.0, 1.0), colors::SLICE_ZERO);
        assert_eq!(diverging_color(-0.0, 1.0), colors::SLICE_ZERO);
        assert_eq!(diverging_color(-1.0, 1.0), colors::SLICE_INSIDE);
        assert_eq!(diverging_color(1.0, 1.0), colors::SLICE_OUTSIDE);
        assert_eq!(diverging_color(f32::NAN, 1.0), [128, 128, 128, 255]);
        // On each side every channel fades monotonically from white as |d|
        // grows (so lightness falls), and the hue is blue inside, red outside.
        let mut last: Option<(f32, [u8; 4])> = None;
        for step in -200..=200 {
            let d = step as f32 / 100.0; // past the scale: clamped
            let colour = diverging_color(d, 1.5);
            let [r, g, b, a] = colour;
            assert_eq!(a, 255);
            if let Some((previous_d, previous)) = last
                && (previous_d < 0.0) == (d < 0.0)
            {
                let (near, far) = if d.abs() > previous_d.abs() {
                    (previous, colour)
                } else {
                    (colour, previous)
                };
                assert!((0..3).all(|k| far[k] <= near[k]), "{d}: {near:?} then {far:?}");
            }
            last = Some((d, colour));
            // Inside is blue with red = green, outside red with green = blue.
            if d < 0.0 {
                assert!(b >= r && r == g, "{d}: {r} {g} {b}");
            } else {
                assert!(r >= b && g == b, "{d}: {r} {g} {b}");
            }
        }
    }

    #[test]
    fn the_zero_contour_crosses_where_the_values_interpolate_to_zero() {
        // f = u - 0.3 on a 4 × 4 grid of the unit square: a straight contour at u = 0.3.
        let bounds = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0));
        let plane = SlicePlane::through(&bounds, Axis::Z, 0.0, 4).unwrap();
        let values: Vec<f32> = plane.points().iter().map(|p| p.x - 0.3).collect();
        let contour = zero_contour(&plane, &values);
        assert_eq!(contour.len(), 3); // one segment per square row
        for [a, b] in &contour {
            assert!((a.x - 0.3).abs() < 1e-5 && (b.x - 0.3).abs() < 1e-5, "{a} {b}");
        }
        // No sign change, no contour; a NaN square is skipped; a wrong length gives nothing.
        let positive: Vec<f32> = values.iter().map(|v| v.abs() + 1.0).collect();
        assert!(zero_contour(&plane, &positive).is_empty());
        let mut holed = values.clone();
        holed[1] = f32::NAN;
        assert_eq!(zero_contour(&plane, &holed).len(), 2);
        assert!(zero_contour(&plane, &values[1..]).is_empty());
        // A saddle (checkerboard square) gives two segments, each cutting off
        // a corner of the sign the centre (the mean) does not have.
        let tiny = SlicePlane::through(&bounds, Axis::Z, 0.0, 2).unwrap();
        for values in [[-1.0, 1.0, 1.0, -3.0], [1.0, -1.0, -1.0, 3.0], [-3.0, 1.0, 1.0, -1.0]] {
            let segments = zero_contour(&tiny, &values);
            assert_eq!(segments.len(), 2);
            let centre_inside = values.iter().sum::<f32>() < 0.0;
            for [a, b] in segments {
                let middle = 0.5 * (a + b);
                let nearest = (0..4)
                    .min_by(|&x, &y| {
                        let px = tiny.point(x % 2, x / 2);
                        let py = tiny.point(y % 2, y / 2);
                        (px - middle).length().total_cmp(&(py - middle).length())
                    })
                    .unwrap();
                assert_ne!(values[nearest] < 0.0, centre_inside, "{values:?}: {a} {b}");
            }
        }
    }

    #[test]
    fn slice_planes_cover_the_grown_box_with_square_cells() {
        let bounds = Aabb::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 4.0, 1.0));
        let plane = SlicePlane::through(&bounds, Axis::X, 0.25, 128).unwrap();
        // In-plane axes of an x slice: y then z.
        assert_eq!(SlicePlane::plane_axes(Axis::X), (1, 2));
        assert_eq!(plane.resolution, [128, 32]);
        assert!((plane.cell[0] - plane.cell[1]).abs() < 1e-6);
        let grown = grown_box(&bounds);
        let c = plane.corners();
        assert_eq!(c[0], Vec3::new(0.25, grown.min.y, grown.min.z));
        assert!((c[2] - Vec3::new(0.25, grown.max.y, grown.max.z)).length() < 1e-5);
        assert_eq!(plane.points().len(), 128 * 32);
        assert_eq!(plane.points()[1], plane.point(1, 0));
        assert!(SlicePlane::through(&Aabb::EMPTY, Axis::X, 0.0, 8).is_err());
        assert!(SlicePlane::through(&bounds, Axis::X, f32::NAN, 8).is_err());
        assert!(SlicePlane::through(&bounds, Axis::X, 0.0, 0).is_err());
        // A flat box still gives a usable plane.
        let flat = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0));
        let side = SlicePlane::through(&flat, Axis::X, 0.5, 16).unwrap();
        assert!(side.cell.iter().all(|&c| c > 0.0) && side.resolution[1] >= 1);
    }

    #[test]
    fn the_readout_gives_both_signs_and_flags_disagreement() {
        let sphere = noisy_icosphere(6, 2);
        let winding = signed_distance_field(&sphere, Sign::WindingNumber).unwrap();
        let pseudo = signed_distance_field(&sphere, Sign::Pseudonormal).unwrap();
        for p in [Vec3::ZERO, Vec3::splat(2.0)] {
            let a = SdfReadout::at(&winding, &winding, p);
            let b = SdfReadout::at(&pseudo, &winding, p);
            // The certified value (an exact integer here) or the tree's, within its accuracy.
            assert!((a.winding_number - winding.winding_number(p)).abs() < 0.04);
            assert!((b.winding_number - a.winding_number).abs() < 0.04);
            assert_eq!(a.inside(), Some(p == Vec3::ZERO));
            assert_eq!(b.inside(), a.inside());
            assert!(!a.methods_disagree() && !b.methods_disagree());
            assert_eq!((a.sign, b.sign), (Sign::WindingNumber, Sign::Pseudonormal));
        }
        // Pseudonormals of a flipped sphere call its inside outside; the
        // winding number is -1 there, so it says outside too (and agrees).
        let faces: Vec<Vec<u32>> = (0..sphere.face_count())
            .map(|f| sphere.face(f).iter().rev().copied().collect())
            .collect();
        let flipped = Mesh::from_faces(sphere.positions().to_vec(), &faces).unwrap();
        let w = signed_distance_field(&flipped, Sign::WindingNumber).unwrap();
        let readout = SdfReadout::at(&w, &w, Vec3::ZERO);
        assert!(readout.winding_number < -0.5 && readout.inside() == Some(false));
        // An open hemisphere-like cut: a point at the centre has w ≈ ½; the
        // methods can disagree there, and the readout says so when they do.
        let fake = SdfReadout {
            signed_distance: pseudo.signed_distance(Vec3::ZERO),
            sign: Sign::Pseudonormal,
            winding_number: 0.2,
        };
        assert!(fake.methods_disagree());
    }

    #[test]
    fn a_mesh_without_faces_has_no_field() {
        let points = Mesh::from_compact(vec![Vec3::ZERO, Vec3::X], vec![0], vec![]).unwrap();
        let error = signed_distance_field(&points, Sign::WindingNumber).unwrap_err();
        assert!(error.contains("no faces"), "{error}");
        assert_eq!(sign_name(Sign::Pseudonormal), "pseudonormal");
    }
}
