//! The paper's passive bending scene (Fig. 2, top of Fig. 8): the residual falls with
//! iterations for both joint flavours, and the exact block solve beats the cheap projection.

use rodlab::constraint::JointFlavour;
use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver, Overrides};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");

/// Mean dislocation (cm) and angular violation (rad) of the first ragdoll over the run.
fn residual(flavour: JointFlavour, iterations: u32) -> (f64, f64) {
    let mut scene = Scene::load(SCENE).unwrap();
    Overrides {
        iterations: Some(iterations),
        joint_flavour: Some(flavour),
        frames: Some(240),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut lab = scene.build().unwrap();
    let report = sim::run(&mut lab, scene.def.frames, &mut NoObserver).unwrap();
    let s = report.ragdolls[0].summary;
    (s.mean_dislocation_cm(), s.mean_angular_rad())
}

#[test]
fn more_iterations_leave_less_residual() {
    for flavour in [JointFlavour::Cheap, JointFlavour::Exact] {
        let (d4, _) = residual(flavour, 4);
        let (d20, _) = residual(flavour, 20);
        assert!(
            d20 < d4,
            "{flavour:?}: 20 iterations {d20} cm vs 4 iterations {d4} cm"
        );
    }
}

#[test]
fn exact_beats_cheap_at_equal_iterations() {
    for iterations in [4, 20] {
        let (cheap, _) = residual(JointFlavour::Cheap, iterations);
        let (exact, _) = residual(JointFlavour::Exact, iterations);
        assert!(
            exact < cheap,
            "{iterations} iterations: exact {exact} cm vs cheap {cheap} cm"
        );
    }
}

/// The paper's result (top of Fig. 8): at 20 iterations the rod spine leaves far less
/// dislocation than the three-joint spine, and both spines slump forward (Fig. 2).
#[test]
fn rod_spine_leaves_less_dislocation_than_chain3() {
    let mut scene = Scene::load(SCENE).unwrap();
    Overrides {
        frames: Some(240),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut lab = scene.build().unwrap();
    let chests: Vec<_> = lab
        .ragdolls
        .iter()
        .map(|r| r.part(&lab.world, "chest").unwrap())
        .collect();
    let start: Vec<_> = chests.iter().map(|&c| lab.world.body(c).position).collect();
    let report = sim::run(&mut lab, scene.def.frames, &mut NoObserver).unwrap();
    let by_spine = |spine: &str| {
        report
            .ragdolls
            .iter()
            .find(|r| r.spine.is_some_and(|s| s.to_string() == spine))
            .unwrap()
            .summary
    };
    let (chain3, rod) = (by_spine("chain3"), by_spine("rod"));
    assert!(
        rod.mean_dislocation_cm() < 0.5 * chain3.mean_dislocation_cm(),
        "rod {} cm vs chain3 {} cm",
        rod.mean_dislocation_cm(),
        chain3.mean_dislocation_cm()
    );
    for (chest, start) in chests.iter().zip(start) {
        let end = lab.world.body(*chest).position;
        assert!(
            end.z > start.z + 0.1 && end.y < start.y - 0.05,
            "chest moved {start} -> {end}"
        );
    }
}
