//! §6: the animation bones posed back from the rod spine. Orientation-only interpolation keeps
//! bone lengths but misses the chest; adding positions closes the gap but stretches bones;
//! riding the arc does well on both. At the transition every method is exact.

use rodlab::lab::Lab;
use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver, Overrides};
use rodlab::skeleton::{BoneError, BoneMethod};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");

fn errors(lab: &Lab, spine: &str) -> Vec<(BoneMethod, BoneError)> {
    let world = &lab.world;
    let ragdoll = lab
        .ragdolls
        .iter()
        .find(|r| r.spine.is_some_and(|s| s.to_string() == spine))
        .unwrap();
    let skeleton = ragdoll.skeleton.as_ref().unwrap();
    skeleton
        .methods()
        .iter()
        .map(|&m| (m, skeleton.error(world, &skeleton.pose(world, m))))
        .collect()
}

fn slumped_lab() -> Lab {
    let mut scene = Scene::load(SCENE).unwrap();
    Overrides {
        frames: Some(120),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut lab = scene.build().unwrap();
    sim::run(&mut lab, scene.def.frames, &mut NoObserver).unwrap();
    lab
}

#[test]
fn every_method_is_exact_at_the_transition() {
    let lab = Scene::load(SCENE).unwrap().build().unwrap();
    for spine in ["chain3", "rod"] {
        for (method, e) in errors(&lab, spine) {
            assert!(
                e.length_cm < 1e-3 && e.chest_gap_cm < 1e-3,
                "{spine} {method:?}: {e:?}"
            );
        }
    }
}

#[test]
fn rod_bone_methods_trade_length_for_gap() {
    let lab = slumped_lab();
    let e: Vec<_> = errors(&lab, "rod");
    let get = |m: BoneMethod| e.iter().find(|(x, _)| *x == m).unwrap().1;
    let (orientation, both, arc) = (
        get(BoneMethod::Orientation),
        get(BoneMethod::OrientationPosition),
        get(BoneMethod::Arc),
    );
    // orientation only: lengths kept, chest missed
    assert!(orientation.length_cm < 1e-3, "{orientation:?}");
    assert!(orientation.chest_gap_cm > 0.5, "{orientation:?}");
    // orientation and position: chest met, lengths changed
    assert!(both.chest_gap_cm < 1e-3, "{both:?}");
    assert!(both.length_cm > 0.1, "{both:?}");
    // the arc: a smaller gap than orientation only and shorter stretches than orientation and
    // position. Its gap is not zero: the chest body carries its bone rigidly along the end
    // tangent, while the arc curves under it.
    assert!(
        arc.chest_gap_cm < orientation.chest_gap_cm,
        "arc {arc:?} vs {orientation:?}"
    );
    assert!(arc.length_cm < both.length_cm, "arc {arc:?} vs {both:?}");
}

#[test]
fn chain3_bones_follow_their_bodies() {
    let lab = slumped_lab();
    for (method, e) in errors(&lab, "chain3") {
        assert_eq!(method, BoneMethod::Rigid);
        assert!(e.chest_gap_cm < 1e-3, "{e:?}");
    }
}
