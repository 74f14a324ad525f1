//! The reference humanoid (`shared/humanoid.md`): 75 kg whatever the spine, and every spine
//! starts satisfied from any starting pose (§6: the rod is instantiated at the transition).

use rodlab::math::{quat_from_degrees, Iso, Vec3};
use rodlab::metrics::ragdoll_residual;
use rodlab::ragdoll::{build_humanoid, HumanoidSpec, SpineKind};
use rodlab::world::{Settings, World};

const SPINES: [SpineKind; 3] = [SpineKind::Chain3, SpineKind::Rod, SpineKind::Single];

#[test]
fn total_mass_is_75_kg_for_every_spine() {
    for spine in SPINES {
        let mut world = World::new(Settings::default());
        let ragdoll = build_humanoid(&mut world, &HumanoidSpec::new("r", spine)).unwrap();
        let mass: f32 = ragdoll.body_ids().map(|id| world.body(id).mass).sum();
        assert!((mass - 75.0).abs() < 0.01, "{spine}: {mass} kg");
        let bodies = ragdoll.bodies.len();
        assert_eq!(
            bodies,
            if spine == SpineKind::Chain3 { 13 } else { 11 },
            "{spine}"
        );
    }
}

#[test]
fn every_spine_starts_satisfied_from_a_bent_twisted_pose() {
    for spine in SPINES {
        let mut world = World::new(Settings::default());
        let mut spec = HumanoidSpec::new("r", spine);
        spec.root = Iso::new(
            Vec3::new(0.3, 0.2, -0.1),
            quat_from_degrees([0.0, 35.0, 10.0]),
        );
        spec.joint_rotations = vec![
            // within every spine's limits (chain3: 25 deg cone, +-15 deg twist per joint)
            ("lumbosacral".into(), quat_from_degrees([15.0, 8.0, 10.0])),
            ("shoulder_l".into(), quat_from_degrees([0.0, 0.0, 60.0])),
            ("knee_r".into(), quat_from_degrees([40.0, 0.0, 0.0])),
        ];
        let ragdoll = build_humanoid(&mut world, &spec).unwrap();
        let residual = ragdoll_residual(&world, &ragdoll);
        assert!(residual.dislocation_cm < 1e-3, "{spine}: {residual:?}");
        assert!(residual.angular_rad < 1e-3, "{spine}: {residual:?}");
    }
}

#[test]
fn unknown_pose_joint_is_an_error() {
    let mut world = World::new(Settings::default());
    let mut spec = HumanoidSpec::new("r", SpineKind::Rod);
    spec.joint_rotations = vec![("thoracolumbar".into(), quat_from_degrees([5.0, 0.0, 0.0]))];
    let err = build_humanoid(&mut world, &spec).unwrap_err();
    assert!(
        err.contains("thoracolumbar") && err.contains("lumbosacral"),
        "{err}"
    );
}
