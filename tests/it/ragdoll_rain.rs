//! The 1000-ragdoll rain (`scenes/ragdoll_rain.toml`): the scene builds, and the full 10 s run
//! without NaN or explosion for both spines, nothing through the floor and the mean
//! dislocation under 1 cm per ragdoll, with the scene's 4 substeps of 2 iterations (SIMD),
//! contact stacking and a 100 rad/s angular speed limit.
//! `cargo test --release --test it ragdoll_rain:: -- --nocapture` prints steps/s.

use rodlab::lab::Lab;
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::sim::{self, Overrides};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ragdoll_rain.toml");

/// Runs the rain with one spine for `frames` frames; returns the final lab, the lowest ragdoll
/// body centre (m) over the run and the mean dislocation per ragdoll (cm).
fn rain(spine: SpineKind, frames: u32) -> (Lab, f32, f32) {
    let mut scene = Scene::load(SCENE).unwrap();
    Overrides {
        spine: Some(spine),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut lab = scene.build().unwrap();
    assert_eq!(lab.ragdolls.len(), 1000);
    // The scene runs 4 substeps of 2 iterations with contact stacking (k = 10). With one
    // substep of 4 iterations the pile presses forearms about 12 cm through the floor at the
    // first impacts (measured: lowest centre -8.6 cm at frame 58, chain3); without stacking 4
    // substeps of 2 iterations leave 1.15 cm per ragdoll (4 of 4 took 0.58 / 0.45 cm), and of
    // 1 iteration throw an elbow past 500 rad/s at the first impacts.
    let settings = &lab.world.settings;
    assert_eq!((settings.substeps, settings.iterations), (4, 2));
    assert_eq!(settings.contact_stacking, 10.0);
    // the spin guard: without it a rounding-level change spun a limb past the explosion bound
    assert_eq!(settings.angular_speed_limit, 100.0);
    let mut lowest = f32::INFINITY;
    let mut observer = |lab: &Lab, _: &rodlab::metrics::FrameMetrics| {
        for r in &lab.ragdolls {
            for id in r.body_ids() {
                lowest = lowest.min(lab.world.body(id).position.y);
            }
        }
    };
    let started = std::time::Instant::now();
    let report =
        sim::run(&mut lab, frames, &mut observer).unwrap_or_else(|e| panic!("{spine}: {e:#}"));
    let seconds = started.elapsed().as_secs_f64();
    let mean =
        report.total_dislocation_cm.iter().sum::<f32>() / report.total_dislocation_cm.len() as f32;
    println!(
        "{spine}: {frames} frames in {seconds:.1} s = {:.1} steps/s (with the metrics); mean \
         total dislocation {mean:.0} cm over 1000 ragdolls, deepest penetration {:.1} cm, lowest \
         body centre {lowest:.3} m; {:.1} steps/s stepping alone",
        frames as f64 / seconds,
        report.max_penetration_cm,
        report.steps_per_second()
    );
    let per_frame = |seconds: f64| 1e3 * seconds / frames as f64;
    let phases: Vec<String> = (report.profile.phases().iter())
        .map(|(name, s)| format!("{name} {:.2}", per_frame(*s)))
        .collect();
    println!("{spine}: ms per frame: {}", phases.join(", "));
    (lab, lowest, mean / 1000.0)
}

#[test]
fn the_scene_builds_a_thousand_ragdolls_and_its_world() {
    let scene = Scene::load(SCENE).unwrap();
    assert_eq!(scene.def.ci_frames, Some(60));
    assert_eq!(scene.def.frames, 600);
    let lab = scene.build().unwrap();
    assert_eq!(lab.ragdolls.len(), 1000);
    let fixed = lab
        .world
        .bodies
        .iter()
        .filter(|b| b.kind == rodlab::body::BodyKind::Fixed)
        .count();
    assert_eq!(fixed, 193, "the floor and 192 tiled boxes");
}

/// The whole 10 s for both spines (about 25 s each): no NaN or explosion (`sim::run` stops
/// with an error), nothing through the floor, and the scene's cost keeping the mean
/// dislocation under 1 cm per ragdoll (measured 0.82 cm chain3, 0.64 cm rod; 0.57 / 0.45 cm at
/// the scene's earlier 4 x 4 without stacking). Under the pile a limb can be pressed into the
/// floor by most of its 4 cm radius (measured: lowest centre +2.2 cm chain3, +3.1 cm rod; +1.0
/// / +1.6 cm at 4 x 4; -5.3 cm with rod before contact impulses moved to fixed lever arms; a
/// chaotic sample that moves with any rounding change), so "through" means a centre more than
/// 10 cm below it. Each spine's rain ends in its committed state (the hash pins the sample).
#[test]
fn ten_seconds_of_rain_stay_finite_on_the_floor_and_under_a_centimetre() {
    for (spine, hash) in [
        (SpineKind::Chain3, 0x8562_fc17_a87a_599e),
        (SpineKind::Rod, 0xfeca_4337_3c11_e4dc),
    ] {
        let (lab, lowest, mean) = rain(spine, 600);
        let what = format!("the rain, {spine}");
        crate::common::assert_state_hash(&what, lab.world.state_hash(), hash);
        assert!(lowest > -0.1, "{spine}: a body centre reached y = {lowest}");
        assert!(
            mean < 1.0,
            "{spine}: mean dislocation {mean} cm per ragdoll"
        );
    }
}

/// The rain's first second (the fall and the first impacts, about 19 000 contact points by the
/// end, so every parallel path runs: broad phase, narrow phase, colours of rows, the contacts'
/// velocity pass, and with joint damping on the dampers' rows) ends bit for bit the same on
/// one thread and on two.
#[test]
fn the_first_second_is_bit_identical_on_one_and_two_threads() {
    let final_state = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut scene = Scene::load(SCENE).unwrap();
            Overrides {
                joint_damping: Some(0.1),
                ..Default::default()
            }
            .apply(&mut scene.def);
            let mut lab = scene.build().unwrap();
            sim::run(&mut lab, 60, &mut sim::NoObserver).unwrap();
            assert!(lab.world.contacts.points.len() > 5000);
            (lab.world.bodies.iter())
                .flat_map(|b| {
                    (b.position.to_array().into_iter())
                        .chain(b.linear_velocity.to_array())
                        .chain(b.angular_velocity.to_array())
                        .chain(b.orientation.to_array())
                        .map(f32::to_bits)
                })
                .collect::<Vec<u32>>()
        })
    };
    assert!(
        final_state(1) == final_state(2),
        "the thread count changed the result"
    );
}
