//! Criterion benchmarks of contacts and the crowd: one step of the 30-ragdoll drop (in the pile)
//! per spine, at the paper's 20 iterations and at the tight method, the broad phase plus narrow phase (`detect`) at 10,
//! 100 and 1000 ragdolls standing on a grid, and one step of 1000 boxes resting on the floor,
//! asleep and awake (what sleeping saves), one step of the drop at its game method falling
//! and settled, and one step of the 1000-ragdoll rain landing and settled (steps/s, and
//! detection per ragdoll; it ends with a table of both), with the landing crowd's
//! broad-phase rebuild alone, from the grid and group by group. Run with `cargo bench
//! --bench drop`; `cargo bench --bench drop -- rain` runs the rain alone (about a minute to
//! settle it first).

use criterion::measurement::WallTime;
use criterion::{
    criterion_group, criterion_main, BatchSize, BenchmarkGroup, BenchmarkId, Criterion, Throughput,
};
use rodlab::body::{Body, BodyKind};
use rodlab::cli::load_scene;
use rodlab::contact::broadphase::BroadPhase;
use rodlab::contact::detect::DetectionProfile;
use rodlab::contact::{collider, detect, Contacts};
use rodlab::lab::Lab;
use rodlab::math::{Iso, Quat, Vec3};
use rodlab::ragdoll::{build_humanoid, HumanoidSpec, SpineKind};
use rodlab::shape::Shape;
use rodlab::sim::{self, NoObserver, Overrides};
use rodlab::solver::Profile;
use rodlab::world::{Settings, World};

/// `file`'s scene (at `variant`, if any) with `spine`, built and stepped: the lab after each
/// of `frames`' counts of frames in turn (a cumulative schedule: `[60, 480]` gives the labs at
/// 1 s and at 9 s).
fn labs_at(file: &str, variant: Option<&str>, spine: SpineKind, frames: &[u32]) -> Vec<Lab> {
    let path = format!("{}/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    let spine = Overrides {
        spine: Some(spine),
        ..Default::default()
    };
    let scene = load_scene(path.as_ref(), variant, &spine).unwrap();
    let mut lab = scene.build().unwrap();
    let mut labs = Vec::new();
    for &n in frames {
        sim::run(&mut lab, n, &mut NoObserver).unwrap();
        labs.push(lab.clone());
    }
    labs
}

/// One step of `world`, each from a fresh copy of it.
fn bench_step(group: &mut BenchmarkGroup<'_, WallTime>, name: String, world: &World) {
    group.bench_function(name, |b| {
        b.iter_batched_ref(
            || world.clone(),
            |w| w.step().unwrap(),
            BatchSize::LargeInput,
        )
    });
}

/// One step of the drop in the pile (2.5 s: the lower layers have landed), per spine, at the
/// paper's method (named by the spine alone) and at the tight method, the method
/// that keeps the landing within 1 cm (20 substeps of one iteration, contacts found every
/// substep and swept six more times, SIMD): what its accuracy costs against the paper's step.
fn drop_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("ragdoll_drop_step");
    group.sample_size(20);
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        for variant in [None, Some("tight")] {
            let lab = &labs_at("ragdoll_drop.toml", variant, spine, &[150])[0];
            let name = match variant {
                None => spine.to_string(),
                Some(variant) => format!("{spine}/{variant}"),
            };
            bench_step(&mut group, name, &lab.world);
        }
    }
    group.finish();
}

/// `count` standing ragdolls 1 m apart on a square grid, over a floor.
fn grid(count: usize) -> World {
    let mut world = World::new(Settings {
        contacts: true,
        ..Settings::default()
    });
    world.add_body(Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0));
    let side = (count as f32).sqrt().ceil() as usize;
    for i in 0..count {
        let mut spec = HumanoidSpec::new(format!("r{i}"), SpineKind::Chain3);
        spec.root = Iso::new(
            Vec3::new((i % side) as f32, 0.0, (i / side) as f32),
            Quat::IDENTITY,
        );
        build_humanoid(&mut world, &spec).unwrap();
    }
    world
}

fn broad_phase_scaling(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact_detection");
    group.sample_size(20);
    for count in [10, 100, 1000] {
        let world = grid(count);
        let mut contacts = Contacts::default();
        contacts.detect(&world.bodies, &world.constraints, 1.0 / 60.0, 0.02); // warm the storage
        group.throughput(Throughput::Elements(count as u64));
        group.bench_with_input(BenchmarkId::from_parameter(count), &world, |b, world| {
            b.iter(|| contacts.detect(&world.bodies, &world.constraints, 1.0 / 60.0, 0.02))
        });
    }
    group.finish();
}

/// 1000 boxes resting on the floor, 0.5 m apart, 20 iterations; stepped 1 s so that with
/// sleeping on every box is asleep (asserted), then one step timed with sleeping on and off.
fn sleeping(c: &mut Criterion) {
    let mut group = c.benchmark_group("sleeping_1000_boxes_step");
    group.sample_size(20);
    for sleep in [true, false] {
        let mut world = World::new(Settings {
            contacts: true,
            sleep,
            ..Settings::default()
        });
        world.add_body(Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0));
        let half = Vec3::new(0.2, 0.1, 0.15);
        for i in 0..1000 {
            let position = Vec3::new(0.5 * (i % 32) as f32, half.y, 0.5 * (i / 32) as f32);
            world.add_body(
                Body::new(
                    format!("box{i}"),
                    BodyKind::Dynamic,
                    Shape::Cuboid { half_extents: half },
                    4.0,
                )
                .with_pose(position, Quat::IDENTITY),
            );
        }
        for _ in 0..60 {
            world.step().unwrap();
        }
        assert_eq!(world.awake_bodies, if sleep { 0 } else { 1000 });
        let name = if sleep { "asleep" } else { "awake" };
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || world.clone(),
                |w| w.step().unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

/// The drop at its game method (4 substeps of 4 iterations, SIMD, exact joints, contacts
/// warm-started and soft at 90 Hz, joint damping 0.2 N m s/rad, sleeping on): one step of the falling
/// pile (at 1 s) against one of the settled pile (at 10 s, all asleep: asserted), per spine.
/// The target: settled at most 20% of falling.
fn settled_against_falling(c: &mut Criterion) {
    let mut group = c.benchmark_group("drop_game_step");
    group.sample_size(20);
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let labs = labs_at("ragdoll_drop.toml", Some("game"), spine, &[60, 540]);
        assert_eq!(
            labs[1].world.awake_bodies, 0,
            "{spine}: the pile is not asleep at 10 s"
        );
        for (phase, lab) in ["falling", "settled"].into_iter().zip(&labs) {
            bench_step(&mut group, format!("{spine}/{phase}"), &lab.world);
        }
    }
    group.finish();
}

/// The 1000-ragdoll rain at its scene's method (4 substeps of 2 iterations, SIMD, contact
/// stacking): one step at 1 s (landing: the first layer meets the geometry) and at 9 s
/// (settled), per spine, on the machine's threads. The targets: 60 steps/s at 2 cores, and
/// detection at most 3 us per ragdoll. The table after the group gives each case's
/// median step, its steps/s and its detection per ragdoll (with each run's median), from the
/// step profiles of three runs of 15 consecutive steps from that state, with detection's broad
/// and narrow phases (`Contacts::detection_profile`) and how many steps rebuilt the kept
/// pairs; a second
/// table splits the broad phase (boxes, kept pairs) and the narrow phase's work summed over
/// its threads (report, shape tests in lanes, points), with the points' cost per point.
fn rain_step(c: &mut Criterion) {
    let cases = [
        "rod/landing",
        "rod/settled",
        "chain3/landing",
        "chain3/settled",
    ];
    let wanted = |case: &str| criterion_filter_matches(&format!("ragdoll_rain_step/{case}"));
    if !cases.iter().any(|case| wanted(case)) {
        return; // filtered out: skip the minute of settling
    }
    let mut group = c.benchmark_group("ragdoll_rain_step");
    group.sample_size(10);
    let mut table = Vec::new();
    for spine in [SpineKind::Rod, SpineKind::Chain3] {
        let labs = labs_at("ragdoll_rain.toml", None, spine, &[60, 480]);
        for (phase, lab) in ["landing", "settled"].into_iter().zip(&labs) {
            let world = &lab.world;
            let case = format!("{spine}/{phase}");
            if !wanted(&case) {
                continue;
            }
            bench_step(&mut group, case.clone(), world);
            if phase == "landing" {
                bench_rebuild(&mut group, &case, world);
            }
            // the step's own profile over 15 consecutive steps, as a run takes them, after one
            // untimed step: criterion's samples each step a fresh copy, whose first step waits
            // on memory a run has in cache (the settled rod's detection: 5.2 against 3.6 ms).
            // Three such runs from the same state: on a shared machine one run's median moved
            // by a fifth from minute to minute, so the table gives each run's too.
            let (mut profiles, mut run_detects, mut contact_points) = (Vec::new(), Vec::new(), 0);
            for _ in 0..RAIN_RUNS {
                let mut w = world.clone();
                w.step().unwrap();
                let run: Vec<_> = (0..RAIN_STEPS)
                    .map(|_| {
                        w.step().unwrap();
                        (w.solver.profile, *w.contacts.detection_profile())
                    })
                    .collect();
                let mut detects: Vec<f64> = run.iter().map(|(step, _)| step.detect).collect();
                detects.sort_by(f64::total_cmp);
                run_detects.push(detects[detects.len() / 2]);
                profiles.extend(run);
                contact_points = w.contacts.points.len();
            }
            let median = |of: &dyn Fn(&(Profile, DetectionProfile)) -> f64| {
                let mut values: Vec<f64> = profiles.iter().map(of).collect();
                values.sort_by(f64::total_cmp);
                values[values.len() / 2]
            };
            table.push(RainRow {
                case,
                step: median(&|(step, _)| step.step),
                detect: median(&|(step, _)| step.detect),
                broad_phase: median(&|(_, detection)| detection.broad_phase),
                narrow_phase: median(&|(_, detection)| detection.narrow_phase),
                rebuilt: profiles.iter().filter(|(_, d)| d.rebuilt).count(),
                boxes: median(&|(_, detection)| detection.broad_phase_parts.boxes),
                kept_pairs: median(&|(_, detection)| detection.broad_phase_parts.pairs),
                report: median(&|(_, detection)| detection.narrow_phase_work.report),
                shape_tests: median(&|(_, detection)| detection.narrow_phase_work.shape_tests),
                points: median(&|(_, detection)| detection.narrow_phase_work.points),
                ragdolls: lab.ragdolls.len() as f64,
                contact_points: contact_points as f64,
                run_detects,
            });
        }
    }
    group.finish();
    println!(
        "\nthe rain, {RAIN_RUNS} runs of {RAIN_STEPS} consecutive steps (median of all), {} \
         thread(s), machine: {}",
        rayon::current_num_threads(),
        rodlab::machine::name()
    );
    println!(
        "case               step ms   steps/s   detect ms   detect us per ragdoll   \
         each run's us    broad phase ms   narrow phase ms   steps rebuilt"
    );
    for row in &table {
        let runs: Vec<String> = (row.run_detects.iter())
            .map(|d| format!("{:.2}", 1e6 * d / row.ragdolls))
            .collect();
        println!(
            "{:<18} {:>7.2}   {:>7.1}   {:>9.2}   {:>21.2}   {:>14}   {:>14.2}   {:>15.2}   {:>7} of {}",
            row.case,
            1e3 * row.step,
            1.0 / row.step,
            1e3 * row.detect,
            1e6 * row.detect / row.ragdolls,
            runs.join(" "),
            1e3 * row.broad_phase,
            1e3 * row.narrow_phase,
            row.rebuilt,
            RAIN_RUNS * RAIN_STEPS,
        );
    }
    println!(
        "\nits parts (median ms): the broad phase's wall time; the narrow phase's work summed \
         over its threads"
    );
    println!(
        "case               boxes   kept pairs   |   report   shape tests   points   \
         points ns per point"
    );
    for row in &table {
        println!(
            "{:<18} {:>5.2}   {:>10.2}   |   {:>6.2}   {:>11.2}   {:>6.2}   {:>19.0}",
            row.case,
            1e3 * row.boxes,
            1e3 * row.kept_pairs,
            1e3 * row.report,
            1e3 * row.shape_tests,
            1e3 * row.points,
            1e9 * row.points / row.contact_points,
        );
    }
}

/// One case of the rain's table: medians over all the runs' steps (s), and how many of them
/// rebuilt the broad phase's pairs.
struct RainRow {
    case: String,
    step: f64,
    detect: f64,
    broad_phase: f64,
    narrow_phase: f64,
    rebuilt: usize,
    ragdolls: f64,
    /// The broad phase's parts, and the narrow phase's work summed over threads (s).
    boxes: f64,
    kept_pairs: f64,
    report: f64,
    shape_tests: f64,
    points: f64,
    /// Contact points found in the last step.
    contact_points: f64,
    /// Each run's median detection (s).
    run_detects: Vec<f64>,
}

/// The rain's table: runs from the same state, and consecutive steps in each.
const RAIN_RUNS: usize = 3;
const RAIN_STEPS: usize = 15;

/// The broad phase's update of `world` with its pairs rebuilt, from the grid and group by group
/// (`broadphase/groups.rs`, the same pairs): what the landing crowd pays every step.
fn bench_rebuild(group: &mut BenchmarkGroup<'_, WallTime>, case: &str, world: &World) {
    let mut colliders = Vec::new();
    collider::build(&world.bodies, &mut colliders);
    let joined = detect::joined(world.bodies.len(), &world.constraints);
    let (dt, margin) = (world.settings.dt, world.settings.contact_margin);
    for (name, grid_only) in [("grid", true), ("groups", false)] {
        let mut broad = BroadPhase::default();
        broad.set_grid_only(grid_only);
        broad.set_joined(joined.clone());
        broad.update(&colliders, dt, margin);
        group.bench_function(format!("{case}/rebuild by {name}"), |b| {
            b.iter_batched_ref(
                || {
                    // new joined pairs: the next update rebuilds
                    let mut broad = broad.clone();
                    broad.set_joined(joined.clone());
                    broad
                },
                |broad| broad.update(&colliders, dt, margin),
                BatchSize::LargeInput,
            )
        });
    }
}

/// Whether criterion's command-line filter (its first free argument, read here as a plain
/// substring) admits `name`, so a filtered run neither settles the rain for nothing nor times
/// cases it skips.
fn criterion_filter_matches(name: &str) -> bool {
    let filter = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    filter.is_none_or(|f| name.contains(&f))
}

criterion_group!(
    benches,
    drop_step,
    broad_phase_scaling,
    sleeping,
    settled_against_falling,
    rain_step
);
criterion_main!(benches);
