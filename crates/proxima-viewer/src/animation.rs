//! The animated demo (`proxima view --animate`): the model deformed every
//! frame by a travelling wave, its structures brought up to date by
//! [`MeshIndex::update_vertices`] (refit in place or rebuilt, as the panel
//! says), and the query point's closest point and a fan of rays answered on
//! the moved surface. Plain data and functions: no egui, no GL.
//!
//! The index holds the two structures a per-frame user (a simulation, a
//! cloth solver, a renderer) keeps: the faces' 4-wide tree for closest
//! points and the 8-wide ray tree for first hits. Both are built at rest
//! when the animation starts, so that every frame after it is an update.

use crate::scene::{self, MeshBuffers, Overlay, Shape, colors};
use proxima::index::{MeshIndex, RefitPolicy};
use proxima::prelude::*;
use std::sync::Arc;
use std::time::Instant;

/// A wave travelling across the model that lifts each vertex along +y:
/// `y += amplitude · sin(2π (x − x₀ + ½ (z − z₀)) / wavelength − 2π t / period)`,
/// with (x₀, z₀) the corner of the model's box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wave {
    /// Largest displacement, in model units.
    pub amplitude: f32,
    /// Length of one wave across the model, in model units.
    pub wavelength: f32,
    /// Seconds per cycle.
    pub period: f32,
    /// Where the phase is counted from (the box's lower corner).
    pub origin: Vec3,
}

impl Wave {
    /// The default amplitude, as a fraction of the box diagonal.
    pub const DEFAULT_AMPLITUDE: f32 = 0.04;
    /// The default period in seconds.
    pub const DEFAULT_PERIOD: f32 = 2.0;

    /// A wave for a model in `bounds`: `amplitude` times the box diagonal
    /// high, two waves across the diagonal, one cycle per `period` seconds.
    /// An empty or non-finite box counts as the cube [−1, 1]³.
    pub fn for_bounds(bounds: &Aabb, amplitude: f32, period: f32) -> Self {
        let b = if bounds.is_empty() || !bounds.is_finite() {
            Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
        } else {
            *bounds
        };
        let diagonal = b.diagonal().max(1e-6);
        Self {
            amplitude: amplitude * diagonal,
            wavelength: 0.5 * diagonal,
            period: if period.is_finite() && period > 0.0 {
                period
            } else {
                Self::DEFAULT_PERIOD
            },
            origin: b.min,
        }
    }

    /// The positions of `rest` at `t` seconds, into `out` (replacing what it
    /// held). The time's phase is taken in `f64`, so that a long-running
    /// animation does not lose it to rounding.
    pub fn displace(&self, rest: &[Vec3], t: f64, out: &mut Vec<Vec3>) {
        let tau = std::f64::consts::TAU;
        let phase = (tau * t / self.period as f64).rem_euclid(tau) as f32;
        let k = std::f32::consts::TAU / self.wavelength;
        out.clear();
        out.extend(rest.iter().map(|&p| {
            let along = (p.x - self.origin.x) + 0.5 * (p.z - self.origin.z);
            p + Vec3::Y * (self.amplitude * (k * along - phase).sin())
        }));
    }
}

/// Rays from one origin, spread over a square of directions.
#[derive(Clone, Debug, PartialEq)]
pub struct RayFan {
    /// Where every ray starts.
    pub origin: Vec3,
    /// Unit directions, row by row.
    pub directions: Vec<Vec3>,
}

impl RayFan {
    /// `side × side` rays from `origin` towards `target`, spread evenly over
    /// the square of directions that holds the sphere of `radius` around
    /// `target` as seen from `origin` (a half-angle of 60° when the origin
    /// is inside it). No rays when `origin` is `target`, either is not
    /// finite, or `side` is 0: the animation goes on without a fan.
    pub fn towards(origin: Vec3, target: Vec3, radius: f32, side: usize) -> Self {
        let axis = (target - origin).try_normalize().filter(|_| origin.is_finite());
        let (Some(axis), true) = (axis, side > 0) else {
            return Self {
                origin,
                directions: Vec::new(),
            };
        };
        let distance = (target - origin).length();
        let half = if radius.is_finite() && distance > radius {
            (radius / distance).asin().tan()
        } else {
            60f32.to_radians().tan()
        };
        let (u, v) = axis.any_orthonormal_pair();
        let step = |i: usize| {
            if side == 1 {
                0.0
            } else {
                half * (2.0 * i as f32 / (side - 1) as f32 - 1.0)
            }
        };
        let directions = (0..side * side)
            .map(|n| (axis + step(n % side) * u + step(n / side) * v).normalize())
            .collect();
        Self { origin, directions }
    }

    /// The fan the viewer casts: from the query point towards the centre of
    /// the model's box, over a sphere of 0.35 of its diagonal (about the
    /// model's own extent, so that most rays come near it).
    pub fn from_query(query: Vec3, bounds: &Aabb, side: usize) -> Self {
        Self::towards(query, bounds.center(), 0.35 * bounds.diagonal(), side)
    }
}

/// How each frame brings the structures up to date.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpdateMode {
    /// Refit the trees in place ([`RefitPolicy::Refit`]).
    #[default]
    Refit,
    /// Build them again ([`RefitPolicy::Rebuild`]).
    Rebuild,
}

impl UpdateMode {
    /// Both modes, in the panel's order.
    pub const ALL: [UpdateMode; 2] = [UpdateMode::Refit, UpdateMode::Rebuild];

    /// The panel's label.
    pub fn name(self) -> &'static str {
        match self {
            UpdateMode::Refit => "refit",
            UpdateMode::Rebuild => "rebuild",
        }
    }

    /// The mode named `refit` or `rebuild`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim() {
            "refit" => Ok(Self::Refit),
            "rebuild" => Ok(Self::Rebuild),
            _ => Err(format!("expected refit or rebuild, got '{text}'")),
        }
    }

    fn policy(self) -> RefitPolicy {
        match self {
            UpdateMode::Refit => RefitPolicy::Refit,
            UpdateMode::Rebuild => RefitPolicy::Rebuild,
        }
    }
}

/// Running means of the seconds one update took, per mode (`None` until the
/// mode has run), so that the panel compares refit and rebuild after the
/// user has tried both.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateTimes {
    /// Seconds per refit.
    pub refit: Option<f64>,
    /// Seconds per rebuild.
    pub rebuild: Option<f64>,
}

impl UpdateTimes {
    /// Weight of the newest frame in the running mean.
    const WEIGHT: f64 = 0.2;

    fn record(&mut self, mode: UpdateMode, seconds: f64) {
        let slot = match mode {
            UpdateMode::Refit => &mut self.refit,
            UpdateMode::Rebuild => &mut self.rebuild,
        };
        *slot = Some(slot.map_or(seconds, |mean| mean + Self::WEIGHT * (seconds - mean)));
    }
}

/// One frame of the animation: the moved mesh's draw buffers and the
/// answers on it.
#[derive(Clone, Debug)]
pub struct AnimationFrame {
    /// Seconds into the animation.
    pub time: f64,
    /// The moved mesh, ready to draw.
    pub buffers: Arc<MeshBuffers>,
    /// The query point.
    pub query: Vec3,
    /// Its closest point on the moved faces.
    pub closest: Option<ClosestHit>,
    /// The fan's rays and their first hits on the moved faces.
    pub fan: RayFan,
    /// The first hit of each of the fan's rays, in its order.
    pub hits: Vec<Option<RayHit>>,
    /// The closest point and the fan, drawn.
    pub overlay: Overlay,
    /// How the structures were brought up to date.
    pub mode: UpdateMode,
    /// Seconds `update_vertices` took.
    pub update_seconds: f64,
    /// Seconds the closest point and the fan's rays took.
    pub query_seconds: f64,
    /// The faces' tree's surface-area cost over its cost at build (NaN
    /// after a rebuild, which has nothing to compare).
    pub cost_ratio: f64,
}

impl AnimationFrame {
    /// How many of the fan's rays hit the mesh.
    pub fn hit_count(&self) -> usize {
        self.hits.iter().filter(|h| h.is_some()).count()
    }
}

/// A deforming copy of the model and its index.
pub struct Animation {
    rest: Vec<Vec3>,
    positions: Vec<Vec3>,
    index: MeshIndex,
    times: UpdateTimes,
}

impl Animation {
    /// Starts an animation of `mesh`: its faces' tree and ray tree built at
    /// rest. Fails when the mesh has no faces (nothing to deform a surface
    /// of), naming the reason.
    pub fn new(mesh: Mesh) -> Result<Self, String> {
        if mesh.face_count() == 0 {
            return Err("the mesh has no faces to animate".into());
        }
        let rest = mesh.positions().to_vec();
        let index = MeshIndex::new(mesh);
        index
            .closest(PrimitiveKind::Faces, &[rest[0]])
            .map_err(|e| e.to_string())?;
        index.ray_tree().map_err(|e| e.to_string())?;
        Ok(Self {
            positions: Vec::with_capacity(rest.len()),
            rest,
            index,
            times: UpdateTimes::default(),
        })
    }

    /// The mesh as last moved.
    pub fn mesh(&self) -> &Mesh {
        self.index.mesh()
    }

    /// Running means of the update times so far.
    pub fn times(&self) -> UpdateTimes {
        self.times
    }

    /// Moves the mesh to `wave` at `t` seconds, updates its structures as
    /// `mode` says (timed), and answers the closest point to `query` and
    /// the first hits of `fan` on the moved surface.
    pub fn step(
        &mut self,
        wave: &Wave,
        t: f64,
        mode: UpdateMode,
        query: Vec3,
        fan: RayFan,
    ) -> Result<AnimationFrame, String> {
        wave.displace(&self.rest, t, &mut self.positions);
        self.index.set_refit_policy(mode.policy());
        let start = Instant::now();
        let updated = self.index.update_vertices(&self.positions).map_err(|e| e.to_string())?;
        let update_seconds = start.elapsed().as_secs_f64();
        self.times.record(mode, update_seconds);
        let cost_ratio = updated
            .iter()
            .find(|u| u.structure == "faces")
            .map_or(f64::NAN, |u| u.cost_ratio);

        let start = Instant::now();
        let closest = self
            .index
            .closest(PrimitiveKind::Faces, &[query])
            .map_err(|e| e.to_string())?[0];
        let rays = self.index.ray_tree().map_err(|e| e.to_string())?;
        let hits = fan
            .directions
            .iter()
            .map(|&d| rays.first_hit(fan.origin, d, 0.0, f32::INFINITY).ok().flatten())
            .collect::<Vec<_>>();
        let query_seconds = start.elapsed().as_secs_f64();

        let overlay = self.overlay(query, closest, &fan, &hits);
        Ok(AnimationFrame {
            time: t,
            buffers: Arc::new(scene::mesh_buffers(self.index.mesh())),
            query,
            closest,
            fan,
            hits,
            overlay,
            mode,
            update_seconds,
            query_seconds,
            cost_ratio,
        })
    }

    /// The fan (hits to their point, misses faintly to past the model) and
    /// the closest point (its face filled, the line to it, both markers).
    fn overlay(&self, query: Vec3, closest: Option<ClosestHit>, fan: &RayFan, hits: &[Option<RayHit>]) -> Overlay {
        let mut overlay = Overlay::default();
        let bounds = self.index.mesh().bounds();
        let reach = (bounds.center() - fan.origin).length() + bounds.diagonal();
        for (&d, hit) in fan.directions.iter().zip(hits) {
            match hit {
                Some(hit) => {
                    overlay.line(fan.origin, hit.point, colors::RAY);
                    overlay.point(hit.point, colors::RAY_HIT, 5.0);
                }
                None => overlay.line(fan.origin, fan.origin + reach * d, colors::FAN_MISS),
            }
        }
        if let Some(hit) = closest {
            let mesh = self.index.mesh();
            let p = mesh.positions();
            let face = Shape::Polygon(mesh.face(hit.source as usize).iter().map(|&i| p[i as usize]).collect());
            overlay.shape(&face, colors::CLOSEST_PRIMITIVE, true);
            overlay.line(query, hit.point, colors::QUERY_LINE);
            overlay.marker(hit.point, colors::CLOSEST, scene::MARKER_SIZE);
        }
        overlay.marker(query, colors::QUERY, scene::MARKER_SIZE);
        overlay
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proxima::{LinearSearch, RayQuery};

    fn bumpy() -> Mesh {
        proxima::mesh::generate::noisy_icosphere(3, 7)
    }

    /// Every answer of a frame against brute force over the moved faces.
    fn check_against_brute_force(frame: &AnimationFrame, moved: &Mesh) {
        let linear = LinearSearch::new(moved.triangles());
        let expected = linear.closest(frame.query).unwrap();
        let got = frame.closest.unwrap();
        assert_eq!(
            got.distance, expected.distance,
            "closest distance at t = {}",
            frame.time
        );
        assert_eq!(got.point, expected.point);
        for (&d, hit) in frame.fan.directions.iter().zip(&frame.hits) {
            let expected = linear.first_hit(frame.fan.origin, d, 0.0, f32::INFINITY).unwrap();
            assert_eq!(hit.map(|h| h.t), expected.map(|h| h.t), "ray {d} at t = {}", frame.time);
        }
    }

    #[test]
    fn every_frame_answers_as_brute_force_on_the_moved_mesh_in_both_modes() {
        let mesh = bumpy();
        let bounds = mesh.bounds();
        let wave = Wave::for_bounds(&bounds, 0.08, 1.0);
        let fan = RayFan::from_query(bounds.min - bounds.size(), &bounds, 7);
        let query = bounds.center() + Vec3::new(0.3, 0.9, 0.2);
        let mut animation = Animation::new(mesh.clone()).unwrap();
        let mut moved = Vec::new();
        let mut hits = 0;
        for step in 0..12 {
            let t = 0.13 * step as f64;
            let mode = UpdateMode::ALL[step % 2];
            let frame = animation.step(&wave, t, mode, query, fan.clone()).unwrap();
            wave.displace(mesh.positions(), t, &mut moved);
            assert_eq!(animation.mesh().positions(), &moved[..]);
            let mut expected = mesh.clone();
            expected.set_positions(&moved).unwrap();
            check_against_brute_force(&frame, &expected);
            assert_eq!(frame.mode, mode);
            assert_eq!(frame.cost_ratio.is_nan(), mode == UpdateMode::Rebuild);
            assert_eq!(frame.buffers.vertices.len(), mesh.vertex_count());
            hits += frame.hit_count();
        }
        // The fan covers the model: some rays hit, some miss.
        assert!(hits > 0 && hits < 12 * 49, "{hits} hits");
        let times = animation.times();
        assert!(times.refit.is_some() && times.rebuild.is_some());
    }

    #[test]
    fn the_wave_moves_only_y_and_by_at_most_its_amplitude() {
        let mesh = bumpy();
        let wave = Wave::for_bounds(&mesh.bounds(), 0.05, 2.0);
        let mut out = Vec::new();
        for t in [0.0, 0.37, 1.0, 1e9 + 0.5] {
            wave.displace(mesh.positions(), t, &mut out);
            assert_eq!(out.len(), mesh.vertex_count());
            for (p, q) in mesh.positions().iter().zip(&out) {
                assert_eq!((p.x, p.z), (q.x, q.z));
                assert!((q.y - p.y).abs() <= wave.amplitude * 1.0001);
            }
        }
        // Periodic in time, and moving between.
        let (mut a, mut b) = (Vec::new(), Vec::new());
        wave.displace(mesh.positions(), 0.25, &mut a);
        wave.displace(mesh.positions(), 2.25, &mut b);
        assert!(a.iter().zip(&b).all(|(p, q)| (*p - *q).length() < 1e-5));
        wave.displace(mesh.positions(), 0.75, &mut b);
        assert!(a.iter().zip(&b).any(|(p, q)| (*p - *q).length() > 0.5 * wave.amplitude));
        // A box that cannot size a wave falls back to the unit cube.
        let w = Wave::for_bounds(&Aabb::EMPTY, 0.1, f32::NAN);
        assert!(w.amplitude > 0.0 && w.wavelength > 0.0 && w.period == Wave::DEFAULT_PERIOD);
    }

    #[test]
    fn fans_cover_the_sphere_and_are_empty_without_a_direction() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let radius = 0.5 * b.diagonal();
        let fan = RayFan::towards(Vec3::new(0.0, 0.0, -10.0), Vec3::ZERO, radius, 5);
        assert_eq!(fan.directions.len(), 25);
        assert!(fan.directions.iter().all(|d| (d.length() - 1.0).abs() < 1e-6));
        // The middle ray is the axis; the corners open to the sphere's angular radius.
        assert!((fan.directions[12] - Vec3::Z).length() < 1e-6);
        let corner_angle = fan.directions[0].angle_between(Vec3::Z);
        let edge_angle = (radius / 10.0).asin();
        assert!(
            corner_angle > edge_angle && corner_angle < 1.5 * edge_angle,
            "{corner_angle}"
        );
        assert_eq!(RayFan::towards(Vec3::ZERO, Vec3::X, 0.1, 1).directions, vec![Vec3::X]);
        assert!(RayFan::towards(Vec3::ZERO, Vec3::ZERO, 1.0, 3).directions.is_empty());
        assert!(RayFan::towards(Vec3::ZERO, Vec3::NAN, 1.0, 3).directions.is_empty());
        assert!(RayFan::towards(Vec3::NAN, Vec3::ZERO, 1.0, 3).directions.is_empty());
        assert!(RayFan::towards(Vec3::ZERO, Vec3::X, 1.0, 0).directions.is_empty());
        // From inside the sphere: a wide fan, still unit directions.
        let inside = RayFan::towards(Vec3::ZERO, Vec3::X, 2.0, 3);
        assert!(inside.directions.iter().all(|d| d.is_finite() && d.x > 0.0));
        // The viewer's fan is aimed at the box's centre.
        let fan = RayFan::from_query(Vec3::new(0.0, 0.0, -10.0), &b, 3);
        assert!((fan.directions[4] - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn modes_parse_by_name() {
        for mode in UpdateMode::ALL {
            assert_eq!(UpdateMode::parse(mode.name()), Ok(mode));
        }
        let e = UpdateMode::parse("both").unwrap_err();
        assert!(e.contains("refit or rebuild") && e.contains("both"), "{e}");
    }

    #[test]
    fn a_mesh_without_faces_cannot_be_animated() {
        let points = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X], &[]).unwrap();
        let e = Animation::new(points).err().unwrap();
        assert!(e.contains("no faces"), "{e}");
    }
}
