//! The signed distance field of a triangle mesh: the closest query's
//! distance, signed by the winding number or by pseudonormals.

use super::certificate::SignCertificate;
use super::pseudonormal::Pseudonormals;
use super::winding::{DEFAULT_BETA, WindingNumbers, winding_number_exact};
use crate::Triangle;
use crate::aabb::Aabb;
use crate::build::BuildConfig;
use crate::error::SdfError;
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::query::{BatchOptions, CHUNK, answer_batch_indexed, closest_announcing, closest_chunk, in_chunks};
use crate::query::{ClosestHit, NearestQuery, SpatialIndex};
use crate::wide_tree::WideTree;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// How the side of a point (inside or outside) is decided.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sign {
    /// Inside where the generalized winding number exceeds ½: right on
    /// open, non-manifold and self-crossing meshes.
    #[default]
    WindingNumber,
    /// The angle-weighted pseudonormal of the closest feature: faster, right
    /// on closed, consistently oriented meshes that do not cross themselves.
    Pseudonormal,
}

impl std::str::FromStr for Sign {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "winding" | "winding-number" => Ok(Self::WindingNumber),
            "pseudonormal" => Ok(Self::Pseudonormal),
            _ => Err(format!("unknown sign method {s:?} (expected winding or pseudonormal)")),
        }
    }
}

/// How a [`SignedDistanceField`] is made.
#[derive(Clone, Debug, PartialEq)]
pub struct SdfConfig {
    /// How the side is decided.
    pub sign: Sign,
    /// The winding numbers' accuracy parameter β ([`DEFAULT_BETA`]).
    pub beta: f32,
    /// Sum the solid angles of every triangle in `f64` instead of using the
    /// tree of expansions: the oracle's answer, linear in the number of
    /// triangles per query.
    pub exact: bool,
    /// With the winding-number sign, decide the side from the closest
    /// query where a [`SignCertificate`] computed at build proves it equal
    /// to the winding number's (closed, manifold, uncrossed parts of the
    /// mesh), and walk the winding number only elsewhere: the same sides,
    /// about the closest query's cost. Off, every signed distance walks the
    /// winding number.
    pub certify: bool,
    /// The tree of the closest queries.
    pub build: BuildConfig,
}

impl Default for SdfConfig {
    fn default() -> Self {
        Self {
            sign: Sign::default(),
            beta: DEFAULT_BETA,
            exact: false,
            certify: true,
            build: BuildConfig::default(),
        }
    }
}

/// The signed distance from a point to a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// The distance to the closest point, negative inside, positive outside
    /// (and on the surface).
    pub distance: f32,
    /// The winding number, when the side came from it: from the tree of
    /// expansions, or, where the field's [`SignCertificate`] decides, the
    /// integer of the closest sheet's side plus the caps' winding number
    /// (an integer on a closed mesh).
    pub winding_number: Option<f32>,
    /// The closest query's answer: the triangle (`primitive`, its face in
    /// `source`), the closest point, the unsigned distance.
    pub closest: ClosestHit,
}

impl SignedDistance {
    /// Whether the point is inside.
    pub fn is_inside(&self) -> bool {
        self.distance < 0.0
    }
}

/// Signed distances, winding numbers and inside tests on a triangle mesh.
///
/// Distances are the closest query's (same triangle, point and distance
/// as [`NearestQuery::closest`]); the sign is negative inside and positive
/// outside, the convention of graphics and of DeepSDF. Inside means a
/// winding number above ½ ([`Sign::WindingNumber`], the default), or
/// behind the pseudonormal of the closest feature ([`Sign::Pseudonormal`]).
///
/// ```
/// use proxima::prelude::*;
/// use proxima::mesh::generate::noisy_icosphere;
/// use proxima::sdf::{SdfConfig, SignedDistanceField};
/// let sphere = noisy_icosphere(8, 1); // radius about 1 around the origin
/// let field = SignedDistanceField::new(&sphere, &SdfConfig::default()).unwrap();
/// let inside = field.signed_distance(Vec3::ZERO).unwrap();
/// assert!(inside.distance < -0.5 && inside.is_inside());
/// assert!(inside.winding_number.unwrap() > 0.5);
/// assert!(field.signed_distance(Vec3::splat(2.0)).unwrap().distance > 0.5);
/// assert!(field.contains(Vec3::ZERO) && !field.contains(Vec3::splat(2.0)));
/// ```
#[derive(Clone, Debug)]
pub struct SignedDistanceField {
    tree: Arc<WideTree<Triangle>>,
    /// Built on first use: a field signed by pseudonormals needs it only
    /// for [`winding_number`](Self::winding_number).
    winding: OnceLock<WindingNumbers>,
    beta: f32,
    /// For the pseudonormal sign (a certificate holds its own).
    pseudonormals: Option<Pseudonormals>,
    certificate: OnceLock<Arc<SignCertificate>>,
    /// Set when the mesh's vertices have moved since the certificate was
    /// made: it is made again later, if the queries pay for it.
    deferred: Option<Deferred>,
    sign: Sign,
    exact: bool,
}

/// A certificate not made again when the mesh's vertices moved (finding
/// its crossings again costs several closest-point batches over the whole
/// mesh, more than most frames of a moving mesh ask), but once the signed
/// distances answered without it have cost about what making it costs.
#[derive(Debug)]
struct Deferred {
    /// Signed distances answered by the walked winding number since.
    walked: AtomicUsize,
    /// When `walked` reaches this, the certificate is made: half the
    /// triangle count. Making it costs about 0.8 µs per triangle on the
    /// dragon, and saves about 1.7 µs per signed distance near its surface
    /// (docs/perf-log.md): never more than about twice the better choice,
    /// in hindsight, of making it at once or never.
    due: usize,
}

impl Deferred {
    /// Nothing walked yet, due at [`certificate_pays`]'s count.
    fn new(triangles: usize) -> Self {
        Self {
            walked: AtomicUsize::new(0),
            due: certificate_due(triangles),
        }
    }
}

/// The signed distances, answered without a certificate, that cost about
/// what making one costs on a mesh of `triangles` triangles: half their
/// number.
const fn certificate_due(triangles: usize) -> usize {
    triangles / 2
}

/// Whether `queries` signed distances on a mesh of `triangles` triangles
/// pay for making the field's [`SignCertificate`] before them: at least
/// half as many as the triangles, the count at which the signed distances
/// it saves have cost about what making it costs (measured in
/// docs/perf-log.md, eighth session). A caller that knows how
/// many it will ask (a grid, a set of training samples) passes the answer
/// to [`SdfConfig::certify`]; with fewer, the field answers by the walked
/// winding number (the same sides).
///
/// ```
/// use proxima::sdf::certificate_pays;
/// assert!(certificate_pays(250_000, 100_000));
/// assert!(!certificate_pays(250_000, 871_414));
/// ```
pub const fn certificate_pays(queries: usize, triangles: usize) -> bool {
    queries >= certificate_due(triangles)
}

impl Clone for Deferred {
    fn clone(&self) -> Self {
        Self {
            walked: AtomicUsize::new(self.walked.load(Ordering::Relaxed)),
            due: self.due,
        }
    }
}

/// A field without its tree, while the tree is refit to moved vertices
/// ([`SignedDistanceField::detach`]).
#[derive(Debug)]
pub(crate) struct Detached {
    winding: Option<WindingNumbers>,
    beta: f32,
    pseudonormals: Option<Pseudonormals>,
    certify: bool,
    sign: Sign,
    exact: bool,
}

impl Detached {
    /// The field again, on `tree`, the detached field's tree refit to
    /// `mesh`'s moved vertices (`rebuilt`: built anew instead): the winding
    /// numbers and the pseudonormals refit over it, the certificate
    /// [deferred](Deferred).
    pub(crate) fn attach(self, tree: Arc<WideTree<Triangle>>, mesh: &Mesh, rebuilt: bool) -> SignedDistanceField {
        let winding = OnceLock::new();
        if let Some(mut numbers) = self.winding {
            if rebuilt {
                numbers = WindingNumbers::new(&tree, self.beta);
            } else {
                numbers.refit(&tree);
            }
            let _ = winding.set(numbers);
        }
        let mut pseudonormals = self.pseudonormals;
        if let Some(normals) = &mut pseudonormals {
            normals.refit(mesh);
        }
        SignedDistanceField {
            tree,
            winding,
            beta: self.beta,
            pseudonormals,
            certificate: OnceLock::new(),
            deferred: self.certify.then(|| Deferred::new(mesh.triangle_count())),
            sign: self.sign,
            exact: self.exact,
        }
    }
}

impl SignedDistanceField {
    /// The field of `mesh`'s faces (fan-triangulated as
    /// [`Mesh::triangles`]). Fails on a mesh without faces or a tree that
    /// cannot be built.
    pub fn new(mesh: &Mesh, config: &SdfConfig) -> Result<Self, SdfError> {
        if mesh.triangle_count() == 0 {
            return Err(SdfError::NoFaces);
        }
        let tree = WideTree::build_set(mesh.triangles(), &config.build)?;
        Ok(Self::with_tree(Arc::new(tree), mesh, config))
    }

    /// The field of `mesh` on `tree`, a tree already built over
    /// `mesh.triangles()` (`config.build` is not used): several fields, or
    /// a field and closest-point queries, then share one tree.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// use proxima::sdf::{SdfConfig, Sign, SignedDistanceField};
    /// use std::sync::Arc;
    /// let mesh = proxima::mesh::generate::noisy_icosphere(4, 1);
    /// let tree = Arc::new(WideTree::build_set(mesh.triangles(), &Default::default()).unwrap());
    /// let config = SdfConfig { sign: Sign::Pseudonormal, ..Default::default() };
    /// let field = SignedDistanceField::with_tree(tree.clone(), &mesh, &config);
    /// assert!(field.contains(Vec3::ZERO));
    /// ```
    pub fn with_tree(tree: Arc<WideTree<Triangle>>, mesh: &Mesh, config: &SdfConfig) -> Self {
        Self::assemble(tree, mesh, config, false)
    }

    /// [`with_tree`](Self::with_tree), except that with
    /// [`SdfConfig::certify`] the certificate is not made now but once the
    /// signed distances answered without it have paid for it (as after
    /// [`MeshIndex::update_vertices`](crate::index::MeshIndex::update_vertices)):
    /// for a field asked fewer signed distances than [`certificate_pays`].
    pub(crate) fn with_tree_deferring(tree: Arc<WideTree<Triangle>>, mesh: &Mesh, config: &SdfConfig) -> Self {
        Self::assemble(tree, mesh, config, true)
    }

    fn assemble(tree: Arc<WideTree<Triangle>>, mesh: &Mesh, config: &SdfConfig, defer: bool) -> Self {
        debug_assert_eq!(tree.len(), mesh.triangle_count());
        // Built now when every signed distance needs it, so that a field's
        // build time holds all of its build.
        let winding = OnceLock::new();
        let certificate = OnceLock::new();
        let mut deferred = None;
        if config.sign == Sign::WindingNumber && !config.exact {
            let numbers = winding.get_or_init(|| WindingNumbers::new(&tree, config.beta));
            match (config.certify, defer) {
                (true, false) => {
                    let _ = certificate.set(Arc::new(SignCertificate::new(mesh, &tree, numbers)));
                }
                (true, true) => deferred = Some(Deferred::new(mesh.triangle_count())),
                (false, _) => {}
            }
        }
        let pseudonormals = (config.sign == Sign::Pseudonormal).then(|| Pseudonormals::new(mesh));
        Self {
            tree,
            winding,
            beta: config.beta,
            pseudonormals,
            certificate,
            deferred,
            sign: config.sign,
            exact: config.exact,
        }
    }

    /// The field without its tree (so that the tree, unshared, can be refit
    /// in place), to [attach](Detached::attach) to it again.
    pub(crate) fn detach(self) -> Detached {
        Detached {
            certify: self.certificate.get().is_some() || self.deferred.is_some(),
            winding: self.winding.into_inner(),
            beta: self.beta,
            pseudonormals: self.pseudonormals,
            sign: self.sign,
            exact: self.exact,
        }
    }

    /// Makes the [deferred](Deferred) certificate once the queries answered
    /// without it have paid for it; `mesh` is the field's mesh, as it is now.
    pub(crate) fn certify_when_due(&self, mesh: &Mesh) {
        if let Some(deferred) = &self.deferred
            && self.certificate.get().is_none()
            && deferred.walked.load(Ordering::Relaxed) >= deferred.due
        {
            self.certificate
                .get_or_init(|| Arc::new(SignCertificate::new(mesh, &self.tree, self.winding_numbers())));
        }
    }

    /// Counts `n` signed distances answered while a deferred certificate
    /// is not made yet.
    #[inline]
    fn count_walked(&self, n: usize) {
        if let Some(deferred) = &self.deferred
            && self.certificate.get().is_none()
        {
            deferred.walked.fetch_add(n, Ordering::Relaxed);
        }
    }

    /// The tree of the closest queries.
    pub fn tree(&self) -> &WideTree<Triangle> {
        &self.tree
    }

    /// The pseudonormals, in a field signed by them or by a certified
    /// winding number.
    pub fn pseudonormals(&self) -> Option<&Pseudonormals> {
        self.pseudonormals
            .as_ref()
            .or_else(|| self.certificate.get().map(|c| c.pseudonormals()))
    }

    /// The certificate that decides the winding number's side from the
    /// closest query, in a field signed by winding numbers and made with
    /// [`SdfConfig::certify`]. After [`MeshIndex::update_vertices`](crate::index::MeshIndex::update_vertices)
    /// it is made again only once the index's signed distances answered
    /// without it number half the mesh's triangles (`None` until then).
    pub fn certificate(&self) -> Option<&SignCertificate> {
        self.certificate.get().map(|c| &**c)
    }

    /// The winding numbers' tree of expansions.
    pub fn winding_numbers(&self) -> &WindingNumbers {
        self.winding.get_or_init(|| WindingNumbers::new(&self.tree, self.beta))
    }

    /// How the side is decided.
    pub fn sign(&self) -> Sign {
        self.sign
    }

    /// The mesh's bounding box.
    pub fn bounds(&self) -> Aabb {
        self.tree.bounds()
    }

    /// The triangles, in the tree's leaf order.
    pub fn triangles(&self) -> &[Triangle] {
        self.tree.leaves().primitives()
    }

    /// The winding number at `p`: by the tree of expansions, or summed over
    /// every triangle in `f64` when the field was made with
    /// [`exact`](SdfConfig::exact). 0 for a `p` that is not finite.
    pub fn winding_number(&self, p: Vec3) -> f32 {
        if self.exact {
            winding_number_exact(self.triangles(), p) as f32
        } else {
            self.winding_numbers().winding_number(p)
        }
    }

    /// Whether the winding number at `p` exceeds ½ (false for a `p` that is
    /// not finite).
    pub fn contains(&self, p: Vec3) -> bool {
        self.winding_number(p) > 0.5
    }

    /// The signed distance at `p`, `None` where [`NearestQuery::closest`]
    /// has no answer (a `p` that is not finite or too large).
    pub fn signed_distance(&self, p: Vec3) -> Option<SignedDistance> {
        // The sign reads the closest triangle's pseudonormal record: asked
        // for as each better triangle is found, it arrives during the walk.
        let closest = match self.pseudonormals() {
            Some(normals) => closest_announcing(&*self.tree, p, |t| normals.prefetch(t))?,
            None => self.tree.closest(p)?,
        };
        Some(self.signed_answer(p, closest))
    }

    /// The closest query's answer `closest` at `p`, signed.
    #[inline]
    pub(crate) fn signed_answer(&self, p: Vec3, closest: ClosestHit) -> SignedDistance {
        self.count_walked(1);
        self.sign_answer(p, closest)
    }

    /// [`signed_answer`](Self::signed_answer) without the count.
    #[inline]
    fn sign_answer(&self, p: Vec3, closest: ClosestHit) -> SignedDistance {
        let (inside, winding_number) = match (self.sign, &self.pseudonormals) {
            (Sign::Pseudonormal, Some(normals)) => (normals.is_inside(closest.primitive, p), None),
            _ => {
                let certified = self.certificate.get().and_then(|c| c.winding_number(&closest, p));
                let w = certified.unwrap_or_else(|| self.winding_number(p));
                (w > 0.5, Some(w))
            }
        };
        SignedDistance {
            distance: if inside { -closest.distance } else { closest.distance },
            winding_number,
            closest,
        }
    }

    /// [`signed_distance`](Self::signed_distance) for every point, on all
    /// cores: in chunks of neighbouring points in Morton order, the distances
    /// as [`NearestQuery::closest_batch`] finds them (each query seeded by
    /// its neighbour's answer), then the chunk's signs while its points and
    /// triangles are in cache. Answers in input order, equal to the single
    /// queries'.
    pub fn signed_distance_batch(&self, points: &[Vec3]) -> Vec<Option<SignedDistance>> {
        let options = BatchOptions::default();
        in_chunks(points, &self.bounds(), options.reorder, None, |chunk, out| {
            let mut hits = [None; CHUNK];
            let hits = &mut hits[..chunk.len()];
            closest_chunk(&*self.tree, chunk, hits, options.seed_radius);
            // The records of the answers a few ahead are fetched while this
            // one is signed: their misses overlap.
            const AHEAD: usize = 8;
            let certificate = self.certificate.get();
            for k in 0..chunk.len() {
                if let (Some(certificate), Some(Some(ahead))) = (certificate, hits.get(k + AHEAD)) {
                    certificate.prefetch(ahead.primitive);
                }
                out[k] = hits[k].map(|hit| self.sign_answer(chunk[k], hit));
            }
            self.count_walked(chunk.len());
        })
    }

    /// [`winding_number`](Self::winding_number) for every point, on all
    /// cores in Morton order; answers in input order.
    pub fn winding_number_batch(&self, points: &[Vec3]) -> Vec<f32> {
        answer_batch_indexed(
            points,
            &self.bounds(),
            true,
            || (),
            |_, i| self.winding_number(points[i]),
        )
    }

    /// [`contains`](Self::contains) for every point, on all cores in Morton
    /// order; answers in input order.
    pub fn contains_batch(&self, points: &[Vec3]) -> Vec<bool> {
        answer_batch_indexed(points, &self.bounds(), true, || (), |_, i| self.contains(points[i]))
    }
}
