//! Collision detection on the 1000-ragdoll rain, rodlab against Rapier on the same state:
//! rodlab's world is stepped to the landing (1 s) and to the settled pile (9 s), chain3
//! spines (Rapier has no rod), then rebuilt in Rapier ([`rodlab::peer::RapierWorld`]) and
//! stepped there. Rapier's time is its own collision-detection timer (broad phase, narrow
//! phase and the final box update, `counters.stages.collision_detection_time`), median over
//! 30 steps after one that builds its pairs; rodlab's is the step profile's detection, median
//! over 15 steps, on one thread and on the machine's. Rapier 0.36 here runs on one thread (its
//! `parallel` feature is off). The pair and point counts differ by design: Rapier keeps a pair
//! for each overlap of its boxes and makes points within its prediction distance (the contact
//! margin); rodlab makes speculative points out to the pair's reach this frame.
//!
//! Run with `cargo bench --features rapier-timers --bench peer` (about a minute after the
//! build).

use rodlab::cli::load_scene;
use rodlab::lab::Lab;
use rodlab::peer::RapierWorld;
use rodlab::ragdoll::SpineKind;
use rodlab::sim::{self, NoObserver, Overrides};

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// rodlab's detection (ms, median) and points per step over 15 steps from a copy of `lab`.
fn rodlab_detection(lab: &Lab) -> (f64, usize) {
    let mut lab = lab.clone();
    let mut times = Vec::new();
    let mut points = 0;
    for _ in 0..15 {
        lab.world.step().unwrap();
        times.push(1e3 * lab.world.solver.profile.detect);
        points += lab.world.contacts.points.len();
    }
    (median(times), points / 15)
}

/// Rapier's collision detection (ms, median), pairs and points per step, from `lab`'s state.
fn rapier_detection(lab: &Lab) -> (f64, usize, usize) {
    let mut rapier = RapierWorld::new(&lab.world, lab.world.settings.substeps).unwrap();
    rapier.physics.physics_pipeline.counters.enable();
    rapier.step(); // builds every pair
    let (mut times, mut pairs, mut points) = (Vec::new(), 0, 0);
    for _ in 0..30 {
        rapier.step();
        let counters = &rapier.physics.physics_pipeline.counters;
        times.push(counters.stages.collision_detection_time.time_ms());
        pairs += counters.cd.ncontact_pairs;
        let manifolds = rapier.physics.narrow_phase.contact_pairs();
        let made: usize = manifolds
            .flat_map(|p| p.manifolds())
            .map(|m| m.points.len())
            .sum();
        points += made;
    }
    (median(times), pairs / 30, points / 30)
}

fn main() {
    let path = format!("{}/scenes/ragdoll_rain.toml", env!("CARGO_MANIFEST_DIR"));
    let chain3 = Overrides {
        spine: Some(SpineKind::Chain3),
        ..Default::default()
    };
    let scene = load_scene(path.as_ref(), None, &chain3).unwrap();
    let mut lab = scene.build().unwrap();
    let threads = rayon::current_num_threads();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    println!("rain, chain3, 1000 ragdolls: collision detection per step (ms, median)");
    println!("| state | Rapier, 1 thread | rodlab, 1 thread | rodlab, {threads} threads | Rapier / rodlab at 1 thread | Rapier pairs, points | rodlab points |");
    println!("|---|---|---|---|---|---|---|");
    let mut done = 0;
    for (state, frame) in [("landing", 60), ("settled", 480)] {
        sim::run(&mut lab, frame - done, &mut NoObserver).unwrap();
        done = frame;
        let (rapier, pairs, rapier_points) = rapier_detection(&lab);
        let (single, points) = one_thread.install(|| rodlab_detection(&lab));
        let (all, _) = rodlab_detection(&lab);
        println!(
            "| {state} | {rapier:.2} | {single:.2} | {all:.2} | {:.1}x | {pairs}, {rapier_points} | {points} |",
            rapier / single
        );
    }
}
