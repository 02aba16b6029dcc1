//! `RigidPose` (pair/pose.rs): constructors that round-trip, random rotations
//! accepted, every kind of non-rigid matrix refused with its own error, the
//! inverse and composition, and `apply` exact under the identity.

use proxima::math::{DMat3, DQuat, DVec3, Vec3};
use proxima::pair::{PoseError, RigidPose};
use proxima::sample::Rng;

fn random_unit_quaternion(rng: &mut Rng) -> [f64; 4] {
    let q = DQuat::from_xyzw(rng.gaussian(), rng.gaussian(), rng.gaussian(), rng.gaussian()).normalize();
    [q.x, q.y, q.z, q.w]
}

fn random_pose(rng: &mut Rng) -> RigidPose {
    let t = [rng.gaussian() * 10.0, rng.gaussian() * 10.0, rng.gaussian() * 10.0];
    RigidPose::from_quaternion(random_unit_quaternion(rng), t).unwrap()
}

/// `p` rotated by the quaternion `q` (scalar last) by the sandwich product
/// `q p q*`, written out: an independent formula for the rotation matrix.
fn rotate_by_quaternion(q: [f64; 4], p: DVec3) -> DVec3 {
    let u = DVec3::new(q[0], q[1], q[2]);
    let w = q[3];
    p * (w * w - u.dot(u)) + u * (2.0 * u.dot(p)) + u.cross(p) * (2.0 * w)
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn random_quaternions_give_rotations_that_round_trip() {
    let mut rng = Rng::new(1);
    for _ in 0..300 {
        let q = random_unit_quaternion(&mut rng);
        let t = [rng.gaussian(), rng.gaussian(), rng.gaussian()];
        let pose = RigidPose::from_quaternion(q, t).unwrap();
        // The matrix equals the sandwich product's rotation.
        let p = DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian());
        let expected = rotate_by_quaternion(q, p) + DVec3::from_array(t);
        assert!(close(pose.apply_f64(p), expected, 1e-14 * (1.0 + p.length())));
        // Through the 4x4 rows and through new(): the same pose, bit for bit.
        assert_eq!(RigidPose::from_rows(pose.to_rows()).unwrap(), pose);
        assert_eq!(RigidPose::new(pose.rotation(), pose.translation()).unwrap(), pose);
        // Rows are [R t; 0 0 0 1]: the translation is the last column.
        let rows = pose.to_rows();
        assert_eq!([rows[0][3], rows[1][3], rows[2][3]], t);
        assert_eq!(rows[3], [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(rows[1][0], pose.rotation().col(0).y);
    }
}

#[test]
fn quaternions_near_unit_are_normalized_others_refused() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // A quarter turn about z given with a norm 1 + 5e-7: accepted, normalized.
    let pose = RigidPose::from_quaternion([0.0, 0.0, h * (1.0 + 5e-7), h * (1.0 + 5e-7)], [0.0; 3]).unwrap();
    assert!(close(pose.apply_f64(DVec3::X), DVec3::Y, 1e-15));
    let err = RigidPose::from_quaternion([0.0, 0.0, 0.0, 1.0 + 2e-6], [0.0; 3]).unwrap_err();
    assert!(
        matches!(err, PoseError::QuaternionNotUnit { norm } if norm == 1.0 + 2e-6),
        "{err:?}"
    );
    assert!(err.to_string().contains("not a unit quaternion"), "{err}");
    assert!(matches!(
        RigidPose::from_quaternion([0.0; 4], [0.0; 3]),
        Err(PoseError::QuaternionNotUnit { .. })
    ));
    assert_eq!(
        RigidPose::from_quaternion([0.0, 0.0, 0.0, f64::NAN], [0.0; 3]),
        Err(PoseError::NotFinite)
    );
    assert_eq!(
        RigidPose::from_quaternion([0.0, 0.0, 0.0, 1.0], [f64::INFINITY, 0.0, 0.0]),
        Err(PoseError::NotFinite)
    );
}

fn rows_of(r: DMat3, t: DVec3) -> [[f64; 4]; 4] {
    let row = |i: usize| [r.col(0)[i], r.col(1)[i], r.col(2)[i], t[i]];
    [row(0), row(1), row(2), [0.0, 0.0, 0.0, 1.0]]
}

#[test]
fn non_rigid_matrices_are_refused_with_their_reason() {
    let mut rng = Rng::new(2);
    let r = random_pose(&mut rng).rotation();
    let t = DVec3::new(1.0, 2.0, 3.0);
    // Scaled: R^T R = s² I, deviation s² - 1.
    let err = RigidPose::from_rows(rows_of(r * 1.01, t)).unwrap_err();
    let PoseError::NotRotation { deviation } = err else {
        panic!("{err:?}")
    };
    assert!((deviation - (1.01f64 * 1.01 - 1.0)).abs() < 1e-12, "{deviation}");
    assert_eq!(
        err.to_string(),
        "the pose is not a rotation: R^T R differs from the identity by 2.0e-2 (tolerance 1e-6); scaled or sheared matrices are not rigid"
    );
    // Sheared.
    let shear = DMat3::from_cols(DVec3::X, DVec3::new(0.01, 1.0, 0.0), DVec3::Z);
    assert!(matches!(
        RigidPose::new(r * shear, t),
        Err(PoseError::NotRotation { .. })
    ));
    // Within the tolerance: accepted as given; just beyond: refused.
    assert!(RigidPose::new(r * (1.0 + 4e-7), t).is_ok());
    assert!(matches!(
        RigidPose::new(r * (1.0 + 6e-7), t),
        Err(PoseError::NotRotation { .. })
    ));
    // Reflected (orthonormal, determinant -1).
    let mirror = DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0));
    assert_eq!(RigidPose::new(r * mirror, t), Err(PoseError::Reflection));
    assert_eq!(
        RigidPose::from_rows(rows_of(-DMat3::IDENTITY, t)),
        Err(PoseError::Reflection)
    );
    assert!(
        RigidPose::new(r * mirror, t)
            .unwrap_err()
            .to_string()
            .contains("reflection")
    );
    // Not finite anywhere.
    let mut rows = rows_of(r, t);
    rows[1][2] = f64::NAN;
    assert_eq!(RigidPose::from_rows(rows), Err(PoseError::NotFinite));
    rows = rows_of(r, t);
    rows[2][3] = f64::NEG_INFINITY;
    assert_eq!(RigidPose::from_rows(rows), Err(PoseError::NotFinite));
    rows = rows_of(r, t);
    rows[3][3] = f64::NAN;
    assert_eq!(RigidPose::from_rows(rows), Err(PoseError::NotFinite));
    assert_eq!(
        RigidPose::translation_only(DVec3::new(0.0, f64::NAN, 0.0)),
        Err(PoseError::NotFinite)
    );
    // A bottom row other than [0, 0, 0, 1] (a transposed matrix, a projection).
    rows = rows_of(r, t);
    rows[3] = [1.0, 2.0, 3.0, 1.0];
    assert_eq!(
        RigidPose::from_rows(rows),
        Err(PoseError::BottomRow {
            row: [1.0, 2.0, 3.0, 1.0]
        })
    );
    rows[3] = [0.0, 0.0, 0.0, 2.0];
    let err = RigidPose::from_rows(rows).unwrap_err();
    assert_eq!(
        err,
        PoseError::BottomRow {
            row: [0.0, 0.0, 0.0, 2.0]
        }
    );
    assert!(err.to_string().contains("bottom row"), "{err}");
}

#[test]
fn inverse_and_composition() {
    let mut rng = Rng::new(3);
    for _ in 0..200 {
        let (a, b) = (random_pose(&mut rng), random_pose(&mut rng));
        let p = DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * 5.0;
        // Inverse undoes, in either order.
        let round_trip = a.then(&a.inverse());
        assert!(close(round_trip.apply_f64(p), p, 1e-12), "{round_trip:?}");
        assert!(close(a.inverse().then(&a).apply_f64(p), p, 1e-12));
        assert!(
            (round_trip.rotation() - DMat3::IDENTITY)
                .to_cols_array()
                .iter()
                .all(|x| x.abs() < 1e-14)
        );
        assert!(round_trip.translation().length() < 1e-13);
        // then() applies self first.
        assert!(close(a.then(&b).apply_f64(p), b.apply_f64(a.apply_f64(p)), 1e-12));
        // A composition is still rigid.
        assert!(RigidPose::new(a.then(&b).rotation(), DVec3::ZERO).is_ok());
    }
}

#[test]
fn identity_applies_exactly_and_poses_in_a_fixed_order() {
    let mut rng = Rng::new(4);
    assert!(RigidPose::IDENTITY.is_identity());
    assert_eq!(RigidPose::default(), RigidPose::IDENTITY);
    assert!(RigidPose::translation_only(DVec3::ZERO).unwrap().is_identity());
    assert!(!RigidPose::translation_only(DVec3::X).unwrap().is_identity());
    let mut specials = vec![
        Vec3::new(-0.0, 0.0, -0.0),
        Vec3::splat(f32::MAX),
        Vec3::splat(f32::MIN_POSITIVE / 8.0),
    ];
    specials.extend((0..1000).map(|_| Vec3::from_array([0; 3].map(|_| f32::from_bits(rng.next_u64() as u32)))));
    let pose = random_pose(&mut rng);
    for p in specials.into_iter().filter(|p| p.is_finite()) {
        let got = RigidPose::IDENTITY.apply(p);
        assert_eq!(
            got.to_array().map(f64::to_bits),
            p.as_dvec3().to_array().map(f64::to_bits),
            "{p:?}"
        );
        // The documented order of operations, bit for bit.
        let (r, t, d) = (pose.rotation(), pose.translation(), p.as_dvec3());
        let expected = DVec3::from_array(std::array::from_fn(|i| {
            ((r.col(0)[i] * d.x + r.col(1)[i] * d.y) + r.col(2)[i] * d.z) + t[i]
        }));
        assert_eq!(pose.apply(p), expected);
    }
    // A translation moves by exactly its amount where that is representable.
    let shift = RigidPose::translation_only(DVec3::new(0.5, -2.0, 8.0)).unwrap();
    assert_eq!(shift.apply(Vec3::new(1.0, 1.0, 1.0)), DVec3::new(1.5, -1.0, 9.0));
    // A quarter turn given as exact rows stays exact.
    let quarter = RigidPose::from_rows([
        [0.0, -1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
    .unwrap();
    assert_eq!(quarter.apply(Vec3::new(1.0, 2.0, 3.0)), DVec3::new(-2.0, 1.0, 3.0));
}
