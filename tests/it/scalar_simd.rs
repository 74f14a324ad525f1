//! The SIMD solve computes the scalar solve's maths W rows at a time, in the same order (both
//! sweep the same coloured rows), so the two agree up to rounding (the lanes' atan2, sin_cos
//! and exp are not libm's): after 60 frames of the scenes without contacts the bodies'
//! positions agree within 5 mm and the residual means within 1%. A pile is chaotic, so there
//! the two differ as any two roundings do; each row solver's pile is pinned by its own state
//! hash (`tests/determinism.rs`), and the lane kernels are held to the scalar ones row by row
//! (`lanes_*.rs`). A thread count never changes a result: the drop's final state is
//! bit-identical with 1 and 2 threads.

use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver, RunReport};
use rodlab::world::{SolverKind, World};

fn scene(name: &str) -> Scene {
    Scene::load(format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn run(scene: &Scene, solver: SolverKind, frames: u32) -> (World, RunReport) {
    let mut lab = scene.build().unwrap();
    lab.world.settings.solver = solver;
    let report = sim::run(&mut lab, frames, &mut NoObserver).unwrap();
    (lab.world, report)
}

fn mean_dislocation(report: &RunReport) -> f64 {
    report
        .ragdolls
        .iter()
        .map(|r| r.summary.mean_dislocation_cm())
        .sum::<f64>()
        / report.ragdolls.len() as f64
}

/// Largest distance (m) between the same body's positions in two worlds.
fn largest_gap(a: &World, b: &World) -> f32 {
    a.bodies
        .iter()
        .zip(&b.bodies)
        .map(|(x, y)| x.position.distance(y.position))
        .fold(0.0, f32::max)
}

fn agree(name: &str, frames: u32, max_gap_m: f32) {
    let scene = scene(name);
    let (scalar, scalar_report) = run(&scene, SolverKind::Scalar, frames);
    let (simd, simd_report) = run(&scene, SolverKind::Simd, frames);
    let gap = largest_gap(&scalar, &simd);
    let (ds, dv) = (
        mean_dislocation(&scalar_report),
        mean_dislocation(&simd_report),
    );
    let relative = (ds - dv).abs() / ds.max(1e-12);
    println!(
        "{name}: largest position gap {:.2e} m after {frames} frames; mean dislocation scalar \
         {ds:.5} cm, simd {dv:.5} cm ({:.3}% apart); colours (joints, rods, contacts) {:?}",
        gap,
        100.0 * relative,
        simd.solver.colour_counts()
    );
    assert!(gap < max_gap_m, "{name}: positions {gap} m apart");
    assert!(
        relative < 0.01,
        "{name}: residual means {:.3}% apart",
        100.0 * relative
    );
}

#[test]
fn passive_bending_agrees() {
    agree("passive_bending", 60, 5e-3);
}

#[test]
fn controllability_agrees() {
    agree("controllability", 60, 5e-3);
}

/// The drop's final state does not depend on the thread count, with either row solver, and
/// with contacts found every substep and swept again alone (the tight method, 80
/// frames of 20 substeps: the fall and the first landings), with either row solver. Detection itself runs on one thread below 4096 bodies; the rain's
/// test (`ragdoll_rain.rs`) covers its parallel path, which detecting every substep reuses.
#[test]
fn drop_is_bit_identical_on_one_and_two_threads() {
    let paper = scene("ragdoll_drop");
    let redetect = paper.variant("tight").unwrap();
    let final_state = |threads: usize, solver: SolverKind, scene: &Scene, frames: u32| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (world, _) = run(scene, solver, frames);
            world
                .bodies
                .iter()
                .flat_map(|b| {
                    [b.position.to_array(), b.linear_velocity.to_array()]
                        .into_iter()
                        .flatten()
                        .chain(b.orientation.to_array())
                        .map(f32::to_bits)
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<u32>>()
        })
    };
    for solver in [SolverKind::Scalar, SolverKind::Simd] {
        assert!(
            final_state(1, solver, &paper, 120) == final_state(2, solver, &paper, 120),
            "{solver}: the thread count changed the result"
        );
    }
    for solver in [SolverKind::Scalar, SolverKind::Simd] {
        assert!(
            final_state(1, solver, &redetect, 80) == final_state(2, solver, &redetect, 80),
            "{solver}, detecting every substep, extra contact sweeps: the thread count changed \
             the result"
        );
    }
}

/// Step 2 keeps the joints', rods' and dampers' rows, their colours and the joints' lanes from
/// frame to frame while the constraints and the bodies' sleep states stay the same. Kept, or
/// prepared afresh every frame, the rod drop at rest (exact joints, joint damping, SIMD,
/// sleeping) gives the same bits: through the frame where the whole pile falls asleep, a
/// rename of a constraint while it sleeps (rows prepared again, none movable), and a kick to
/// one body that wakes it (rows kept from the sleeping pile would leave the woken joints out).
#[test]
fn rows_kept_from_frame_to_frame_give_the_bits_of_rows_prepared_afresh() {
    use rodlab::constraint::Constraint;
    use rodlab::ragdoll::SpineKind;
    use rodlab::sim::Overrides;
    let mut scene = scene("ragdoll_drop").variant("game").unwrap();
    Overrides {
        spine: Some(SpineKind::Rod),
        ..Default::default()
    }
    .apply(&mut scene.def);
    assert!(scene.def.sleep && scene.def.joint_damping > 0.0);
    let mut kept = scene.build().unwrap().world;
    let mut afresh = kept.clone();
    let (mut all_asleep, mut kicked) = (None, None);
    for frame in 0..600 {
        // a rename while the pile sleeps: the rows are prepared again, none of them movable
        if all_asleep.is_some_and(|f| frame == f + 10) {
            for world in [&mut kept, &mut afresh] {
                match &mut world.constraints[0] {
                    Constraint::Rod(rod) => rod.name.push_str(" (renamed)"),
                    Constraint::BallSocket(joint) => joint.name.push_str(" (renamed)"),
                }
            }
        }
        if all_asleep.is_some_and(|f| frame == f + 20) {
            for world in [&mut kept, &mut afresh] {
                world.bodies[5].linear_velocity = rodlab::math::Vec3::new(0.0, 3.0, 0.0);
            }
            kicked = Some(frame);
        }
        kept.step().unwrap();
        afresh.solver.clear_prepared();
        afresh.step().unwrap();
        assert_eq!(
            kept.state_hash(),
            afresh.state_hash(),
            "frame {frame}: the kept rows gave other bits"
        );
        if kept.awake_bodies == 0 && all_asleep.is_none() {
            all_asleep = Some(frame);
        }
        if kicked.is_some_and(|f| frame == f + 2) {
            assert!(
                kept.awake_bodies > 10,
                "the kick woke {} bodies",
                kept.awake_bodies
            );
            return;
        }
    }
    panic!("the pile never fell asleep (at {all_asleep:?}) and woke: the test saw no change");
}

/// A constraint edited between steps takes effect at the next step: editing it draws a new
/// stamp ([`rodlab::constraint::Constraints`]), so step 2 does not reuse the old rows. A
/// pendulum's joint is moved 10 cm down the bob after 20 frames; the run matches one that
/// prepares its rows afresh, and differs from one without the edit.
#[test]
fn a_constraint_edited_between_steps_takes_effect_at_the_next_step() {
    use rodlab::body::{Body, BodyKind};
    use rodlab::constraint::{BallSocket, Constraint};
    use rodlab::math::{Quat, Vec3};
    use rodlab::shape::Shape;
    use rodlab::world::Settings;
    let mut world = World::new(Settings::default());
    let sphere = |radius| Shape::Sphere { radius };
    let pivot = Vec3::new(0.0, 2.0, 0.0);
    let fixed = Body::new("pivot", BodyKind::Fixed, sphere(0.02), 1.0);
    let fixed = world.add_body(fixed.with_pose(pivot, Quat::IDENTITY));
    let bob = Body::new("bob", BodyKind::Dynamic, sphere(0.05), 1.0);
    let bob_at = pivot + Vec3::new(0.4, -0.3, 0.0);
    let bob = world.add_body(bob.with_pose(bob_at, Quat::IDENTITY));
    let bodies = &world.bodies;
    let joint = BallSocket::at_world_anchor("hinge", bodies, fixed, bob, pivot, Quat::IDENTITY);
    world.add_constraint(joint);
    for _ in 0..20 {
        world.step().unwrap();
    }
    let mut unedited = world.clone();
    if let Constraint::BallSocket(joint) = &mut world.constraints[0] {
        joint.local_anchor_b += Vec3::new(0.0, 0.1, 0.0);
    }
    let mut afresh = world.clone();
    for _ in 0..20 {
        world.step().unwrap();
        unedited.step().unwrap();
        afresh.solver.clear_prepared();
        afresh.step().unwrap();
    }
    assert_eq!(world.state_hash(), afresh.state_hash());
    let moved = world.bodies[bob.index()].position - unedited.bodies[bob.index()].position;
    assert!(moved.length() > 0.05, "the edit moved the bob by {moved}");
}
