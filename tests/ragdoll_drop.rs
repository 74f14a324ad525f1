//! The 30-ragdoll drop (paper Fig. 1, bottom of Fig. 8): ten seconds without NaN, nothing
//! through the floor, nearly all bodies at rest at the end, and the rod spine leaving less
//! dislocation than the three-joint spine.

use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::sim::{self, Overrides};
use rodlab::world::World;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ragdoll_drop.toml");

/// Runs the drop with one spine; returns the final world and the mean total dislocation (cm).
fn drop(spine: SpineKind) -> (World, f32, f32) {
    let mut scene = Scene::load(SCENE).unwrap();
    Overrides {
        spine: Some(spine),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut world = scene.build().unwrap();
    assert_eq!(world.ragdolls.len(), 30);
    let mut lowest = f32::INFINITY;
    let mut observer = |w: &World, _: &rodlab::metrics::FrameMetrics| {
        for r in &w.ragdolls {
            for id in r.body_ids() {
                let body = w.body(id);
                lowest = lowest.min(body.position.y);
            }
        }
    };
    let report =
        sim::run(&mut world, scene.def.frames, &mut observer).expect("no NaN, no explosion");
    let mean =
        report.total_dislocation_cm.iter().sum::<f32>() / report.total_dislocation_cm.len() as f32;
    (world, mean, lowest)
}

#[test]
fn thirty_ragdolls_land_and_settle_and_the_rod_spine_leaves_less_residual() {
    let mut means = Vec::new();
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let (world, mean, lowest) = drop(spine);
        // body centres stay above the floor (the thinnest limb has a 4 cm radius)
        assert!(lowest > 0.0, "{spine}: a body centre reached y = {lowest}");
        let fastest = world
            .ragdolls
            .iter()
            .flat_map(|r| r.body_ids())
            .map(|id| world.body(id).linear_velocity.length())
            .fold(0.0, f32::max);
        let speeds: Vec<f32> = world
            .ragdolls
            .iter()
            .flat_map(|r| r.body_ids())
            .map(|id| world.body(id).linear_velocity.length())
            .collect();
        let resting = speeds.iter().filter(|&&v| v < 0.2).count() as f32 / speeds.len() as f32;
        // Not yet every body: a few limbs caught in the concave corners between stair boxes
        // keep jittering (see the README's status); the rest of the pile is at rest.
        // measured: chain3 99.2% (fastest 0.29 m/s), rod 98.8% (fastest 0.49 m/s)
        assert!(
            resting > 0.98,
            "{spine}: only {:.1}% of bodies at rest",
            100.0 * resting
        );
        assert!(
            fastest < 1.0,
            "{spine}: a body still moves at {fastest} m/s after 10 s"
        );
        means.push(mean);
    }
    assert!(
        means[1] < means[0],
        "mean total dislocation: rod {} cm vs chain3 {} cm",
        means[1],
        means[0]
    );
}
