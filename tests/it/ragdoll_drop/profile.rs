//! The step's and detection's profiles on the drop account for their time.

use super::*;
use rodlab::scene::Scene;
use rodlab::sim;

/// The step profile accounts for the step: every phase the drop runs takes time, and the
/// phases add up to the step's own wall time, timed where the step runs (`Profile::step`).
/// The caller's time around `World::step` is not the yardstick: it adds the hand-over onto
/// rayon's pool, whose wake-up latency on a loaded 2-core machine ranged up to a quarter of a
/// 2 ms step (CI measured 76% of it in phases), and that says nothing about the profile.
#[test]
fn the_step_profile_accounts_for_the_step() {
    let _alone = one_at_a_time();
    let mut lab = Scene::load(SCENE).unwrap().build().unwrap();
    // one untimed frame first: the first step starts rayon's threads
    sim::run(&mut lab, 1, &mut sim::NoObserver).unwrap();
    let report = sim::run(&mut lab, 20, &mut sim::NoObserver).unwrap();
    let p = report.profile;
    for (name, seconds) in p.phases() {
        let runs = name != "rods" && name != "sleep"; // chain3 spines: no rods; sleep is off
        assert!(!runs || seconds > 0.0, "{name}: {seconds} s");
    }
    let (total, step, outside) = (p.total(), p.step, report.step_seconds);
    println!("profile {total:.6} s of {step:.6} s stepping ({outside:.6} s around the calls)");
    assert!(total <= step, "phases {total} s exceed the step's {step} s");
    assert!(
        step <= outside,
        "the step's {step} s exceed the {outside} s around it"
    );
    assert!(
        total > 0.95 * step,
        "phases {total} s of the step's {step} s: a part of the step is in no phase"
    );
}

/// Detection's pieces (`Contacts::detection_profile`) lie within the step's detect phase, and
/// the broad and narrow phases' parts within them; a new world's first detection rebuilds its
/// pairs, and every body pair with a point was tested.
#[test]
fn the_detection_profile_accounts_for_detection() {
    let _alone = one_at_a_time();
    let mut lab = Scene::load(SCENE).unwrap().build().unwrap();
    lab.step().unwrap();
    let first = *lab.world.contacts.detection_profile();
    assert!(
        first.rebuilt,
        "a new world's first detection rebuilds: {first:?}"
    );
    sim::run(&mut lab, 90, &mut sim::NoObserver).unwrap(); // the pile has formed
    for _ in 0..20 {
        lab.step().unwrap();
        let d = *lab.world.contacts.detection_profile();
        // the broad phase and the handover run side by side on two threads, one after the
        // other on one
        let pieces = d.records + d.broad_phase.max(d.handover) + d.narrow_phase + d.concatenate;
        let detect = lab.world.solver.profile.detect;
        assert!(
            pieces <= detect,
            "pieces {pieces} s of detect's {detect} s: {d:?}"
        );
        // the broad phase's parts lie within it; the narrow phase's work, summed over its
        // threads, within its wall time on each thread, and some of it goes to every part
        let broad = d.broad_phase_parts;
        assert!(broad.boxes > 0.0 && broad.pairs > 0.0, "{d:?}");
        assert!(broad.boxes + broad.pairs <= d.broad_phase, "{d:?}");
        let work = d.narrow_phase_work;
        let threads = rayon::current_num_threads() as f64;
        assert!(
            work.report > 0.0 && work.shape_tests > 0.0 && work.points > 0.0,
            "{d:?}"
        );
        assert!(
            work.report + work.shape_tests + work.points <= threads * d.narrow_phase,
            "{d:?}"
        );
        let mut pairs: Vec<(u32, u32)> = (lab.world.contacts.points.iter())
            .map(|p| (p.body_a.0, p.body_b.0))
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        assert!(!pairs.is_empty(), "the pile touches");
        assert!(
            pairs.len() <= d.pairs_tested,
            "{} pairs with points, {} tested",
            pairs.len(),
            d.pairs_tested
        );
    }
}
