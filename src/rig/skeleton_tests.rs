//! The game's 71-joint animation skeleton: the reader and its errors, the handover's poses,
//! and every joint posed back from a character's bodies (paper §6).

use super::*;
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::{quat_from_degrees, Quat, Vec3};
use crate::scene::Scene;
use crate::sim::{self, NoObserver};
use crate::skeleton::BoneError;

const RIGS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/rigs/jolt-human");

/// The spine chain of the animation skeleton, hips to chest.
const SPINE: [&str; BONES] = [
    "hipsBone",
    "C_Spine_sjnt_0",
    "C_Spine_sjnt_1",
    "C_Spine_sjnt_2",
    "C_Spine_sjnt_3",
    "C_Spine_sjnt_4",
];

const ALL_METHODS: [BoneMethod; 4] = [
    BoneMethod::Rigid,
    BoneMethod::Orientation,
    BoneMethod::OrientationPosition,
    BoneMethod::Arc,
];

fn hd() -> AnimationSkeleton {
    AnimationSkeleton::load(format!("{RIGS}/skeleton_hd.tof")).unwrap()
}

fn clip(name: &str) -> Animation {
    Animation::load(format!("{RIGS}/{name}")).unwrap()
}

fn neutral_locals(skeleton: &AnimationSkeleton) -> Vec<Iso> {
    skeleton.locals_from(&clip("neutral_hd.tof")).unwrap()
}

/// Whether two poses agree within `metres` and `radians` (the angle between the rotations as
/// twice the distance between the unit quaternions, which stays accurate at small angles).
fn same_pose(a: &Iso, b: &Iso, metres: f32, radians: f32) -> bool {
    let (p, q) = (a.rotation, b.rotation);
    let angle = 2.0 * (p - q).length().min((p + q).length());
    a.translation.distance(b.translation) < metres && angle < radians
}

/// A built scene of `scenes/`, run for `frames` after its handover.
fn lab(scene: &str, frames: u32) -> Lab {
    let path = format!("{}/scenes/{scene}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut lab = Scene::load(path).unwrap().build().unwrap();
    // a clip played before the handover: to the handover frame, the bodies put at its pose
    let handover = lab.playbacks.first().map_or(0, |p| p.handover_frame()) as u32;
    sim::run(&mut lab, handover, &mut NoObserver).unwrap();
    lab.playbacks
        .iter_mut()
        .for_each(|p| p.pose(&mut lab.world));
    sim::run(&mut lab, frames, &mut NoObserver).unwrap();
    lab
}

/// The character `name` of `lab`, its spine skeleton and its mapped animation skeleton.
fn character<'a>(lab: &'a Lab, name: &str) -> (&'a Skeleton, &'a MappedSkeleton) {
    let ragdoll = lab.ragdolls.iter().find(|r| r.name == name).unwrap();
    let mapped = ragdoll.hd_skeleton.as_ref().unwrap();
    (ragdoll.skeleton.as_ref().unwrap(), mapped)
}

fn errors(lab: &Lab, skeleton: &Skeleton, method: BoneMethod) -> BoneError {
    skeleton.error(&lab.world, &skeleton.pose(&lab.world, method))
}

/// 71 joints, parents first, rooted at `rootBone` above the hips; its spine has the fifth
/// joint the ragdoll lacks; every part of the ragdoll is a joint whose nearest ancestor among
/// the parts is the part's parent in the ragdoll.
#[test]
fn the_animation_skeleton_has_71_joints_around_the_ragdolls_23() {
    let skeleton = hd();
    assert_eq!(
        (skeleton.name.as_str(), skeleton.joints.len()),
        ("skeleton_hd", 71)
    );
    assert_eq!(skeleton.joints[0].name, "rootBone");
    assert_eq!(skeleton.joints[0].parent, None);
    let roots = skeleton
        .joints
        .iter()
        .filter(|j| j.parent.is_none())
        .count();
    assert_eq!(roots, 1);
    let mut ordered = skeleton.joints.iter().enumerate();
    assert!(ordered.all(|(i, j)| j.parent.is_none_or(|p| p < i)));
    let parent = |name: &str| {
        let p = skeleton.joints[skeleton.joint_index(name).unwrap()].parent;
        p.map(|p| skeleton.joints[p].name.as_str())
    };
    for (child, expected) in [
        ("hipsBone", "rootBone"),
        ("C_Spine_sjnt_4", "C_Spine_sjnt_3"),
        ("C_Neck_sjnt_0", "C_Spine_sjnt_4"),
        ("R_Index_sjnt_0", "R_Wrist_sjnt_0"),
        ("L_Pinky_sjnt_3", "L_Pinky_sjnt_2"),
        ("R_Prop_fjnt_0", "R_Wrist_sjnt_0"),
        ("L_Foot_sjnt_2", "L_Foot_sjnt_1"),
    ] {
        assert_eq!(parent(child), Some(expected), "{child}");
    }
    let chain = skeleton.spine_chain("hipsBone", "C_Spine_sjnt_4").unwrap();
    assert_eq!(chain.map(|j| skeleton.joints[j].name.as_str()), SPINE);
    let fingers = ["Thumb", "Index", "Middle", "Ring", "Pinky"];
    let is_finger = |j: &&SkeletonJoint| fingers.iter().any(|f| j.name.contains(f));
    assert_eq!(skeleton.joints.iter().filter(is_finger).count(), 40);
    let rig = Rig::load(format!("{RIGS}/Human.tof")).unwrap();
    for part in &rig.parts {
        let mut at = skeleton.joint_index(&part.joint_name).unwrap();
        let ancestor_part = loop {
            match skeleton.joints[at].parent {
                Some(p) if rig.part_index(&skeleton.joints[p].name).is_some() => break Some(p),
                Some(p) => at = p,
                None => break None,
            }
        };
        let name = ancestor_part.map(|p| skeleton.joints[p].name.as_str());
        let expected = part.parent.map(|p| rig.parts[p].joint_name.as_str());
        assert_eq!(name, expected, "{}", part.joint_name);
    }
}

/// Joint `i`'s name stands on line `12 + 2 i` of the file and its parent's name on the next.
#[test]
fn a_broken_skeleton_names_the_file_line_and_field() {
    let text = std::fs::read_to_string(format!("{RIGS}/skeleton_hd.tof")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[12 + 2 * 5 - 1].trim(), "\"C_Spine_sjnt_3\"");
    let with = |line: usize, value: &str| {
        let mut edited = lines.clone();
        let quoted = format!("      \"{value}\"");
        edited[line - 1] = &quoted;
        AnimationSkeleton::from_str(&edited.join("\n"), "skeleton_hd.tof").unwrap_err()
    };
    let cases = [
        (
            12 + 2 * 3,
            "C_Spine_sjnt_0",
            "mJoints[3].mName",
            "also names joint 2",
        ),
        (12 + 2 * 4, "", "mJoints[4].mName", "a joint has no name"),
        (
            13 + 2 * 5,
            "C_Spine_sjnt_9",
            "mJoints[5].mParentName",
            "no joint is named",
        ),
        (
            13 + 2 * 2,
            "C_Spine_sjnt_2",
            "mJoints[2].mParentName",
            "listed after its child",
        ),
        (
            13 + 2 * 6,
            "C_Spine_sjnt_4",
            "mJoints[6].mParentName",
            "its own parent",
        ),
    ];
    for (line, value, field, message) in cases {
        let error = with(line, value);
        let prefix = format!("skeleton_hd.tof:{line}: Skeleton 00000001 field {field}: ");
        assert!(error.starts_with(&prefix), "{error}");
        assert!(error.contains(message), "{error}");
    }
    let ragdoll = std::fs::read_to_string(format!("{RIGS}/Human.tof")).unwrap();
    let error = AnimationSkeleton::from_str(&ragdoll, "Human.tof").unwrap_err();
    assert!(
        error.contains("Human.tof:") && error.contains("expected Skeleton"),
        "{error}"
    );
    // a file cut at any line is read or refused, never a panic
    for cut in 0..lines.len() {
        let _ = AnimationSkeleton::from_str(&lines[..cut].join("\n"), "skeleton_hd.tof");
    }
}

/// The neutral pose keys all 71 joints; the ragdoll's own clip lacks the root and is refused.
#[test]
fn the_neutral_pose_keys_every_joint() {
    let skeleton = hd();
    assert_eq!(neutral_locals(&skeleton).len(), 71);
    let error = skeleton.locals_from(&clip("neutral.tof")).unwrap_err();
    assert!(
        error.contains("\"rootBone\"") && error.contains("neutral"),
        "{error}"
    );
}

/// 1 s into the walk, placed and turned: every joint named like a part takes the part's pose,
/// every other joint below a parent its neutral local transform, and the root its neutral
/// offset from the hips. The ragdoll's neutral clip puts the mapped joints where the
/// skeleton's own neutral pose does.
#[test]
fn at_the_handover_mapped_joints_take_their_parts_poses() {
    let (skeleton, rig) = (hd(), Rig::load(format!("{RIGS}/Human.tof")).unwrap());
    let locals = neutral_locals(&skeleton);
    let neutral = skeleton.world_from_local(&locals);
    let place = Iso::new(
        Vec3::new(0.5, 0.8, -3.05),
        quat_from_degrees([0.0, 180.0, 0.0]),
    );
    let parts: Vec<Iso> = (rig.pose(&clip("walk.tof"), 1.0).iter())
        .map(|p| place * *p)
        .collect();
    let poses = skeleton.handover_poses(&locals, &rig, &parts);
    let mut mapped = 0;
    for (j, joint) in skeleton.joints.iter().enumerate() {
        match (rig.part_index(&joint.name), joint.parent) {
            (Some(part), _) => {
                mapped += 1;
                assert!(
                    same_pose(&poses[j], &parts[part], 1e-5, 1e-5),
                    "{}",
                    joint.name
                );
            }
            (None, Some(p)) => {
                let local = poses[p].inverse() * poses[j];
                assert!(same_pose(&local, &locals[j], 1e-5, 1e-5), "{}", joint.name);
            }
            (None, None) => {
                let hips = skeleton.joint_index("hipsBone").unwrap();
                let offset = poses[hips].inverse() * poses[j];
                let neutral_offset = neutral[hips].inverse() * neutral[j];
                assert!(
                    same_pose(&offset, &neutral_offset, 1e-5, 1e-5),
                    "{}",
                    joint.name
                );
            }
        }
    }
    assert_eq!(mapped, 23);
    let standing = skeleton.handover_poses(&locals, &rig, &rig.pose(&clip("neutral.tof"), 0.0));
    for (j, (a, b)) in standing.iter().zip(&neutral).enumerate() {
        let name = &skeleton.joints[j].name;
        assert!(same_pose(a, b, 2e-5, 2e-3), "{name}: {a:?} against {b:?}");
    }
}

/// The walk scene's two characters at the handover: every method poses all 71 joints where
/// the handover put them, with no bone error; the rig spine is posed rigidly, its fifth joint
/// riding the part that spans it, and the rod spine by the three rod methods.
#[test]
fn at_the_handover_every_method_poses_every_joint_where_it_stands() {
    let lab = lab("rig_walk_to_ragdoll", 0);
    for name in ["rig", "rod"] {
        let (spine, mapped) = character(&lab, name);
        assert_eq!(mapped.names().len(), 71);
        assert_eq!(mapped.parents().len(), 71);
        for method in ALL_METHODS {
            let poses = mapped.pose(&lab.world, method);
            for (j, (posed, expected)) in poses.iter().zip(mapped.at_handover()).enumerate() {
                let joint = &mapped.names()[j];
                assert!(
                    same_pose(posed, expected, 1e-5, 1e-5),
                    "{name} {method:?} {joint}: {posed:?} against {expected:?}"
                );
            }
            let e = errors(&lab, spine, method);
            assert!(
                e.length_cm < 1e-4 && e.chest_gap_cm < 1e-4,
                "{name} {method:?} {e:?}"
            );
        }
        let body_names = spine.bodies().map(|b| lab.world.body(b).name.clone());
        let own = |k: usize| format!("{name}/{}", SPINE[k]);
        let expected = match name {
            "rig" => [own(0), own(1), own(2), own(3), own(3), own(5)],
            _ => [own(0), own(0), own(0), own(5), own(5), own(5)],
        };
        assert_eq!(body_names, expected);
    }
    let (rig_spine, _) = character(&lab, "rig");
    assert_eq!(rig_spine.methods(), [BoneMethod::Rigid]);
    let (rod_spine, _) = character(&lab, "rod");
    assert_eq!(rod_spine.methods(), &ALL_METHODS[1..]);
}

/// Moving every body of the world by one rigid transform moves all 71 joints by it, by every
/// method, half a second into the walk's fall (the rod bent, the limbs swung).
#[test]
fn moving_the_whole_character_rigidly_moves_every_joint_with_it() {
    let mut lab = lab("rig_walk_to_ragdoll", 30);
    let before: Vec<Vec<Vec<Iso>>> = ["rig", "rod"]
        .map(|name| {
            ALL_METHODS
                .map(|m| character(&lab, name).1.pose(&lab.world, m))
                .to_vec()
        })
        .to_vec();
    let turn = (Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.7)).normalize();
    let transform = Iso::new(Vec3::new(1.2, -0.3, 2.0), turn);
    for body in &mut lab.world.bodies {
        body.position = transform.transform_point(body.position);
        body.orientation = (turn * body.orientation).normalize();
    }
    for (c, name) in ["rig", "rod"].into_iter().enumerate() {
        let mapped = character(&lab, name).1;
        for (m, method) in ALL_METHODS.into_iter().enumerate() {
            let after = mapped.pose(&lab.world, method);
            for (j, (a, b)) in after.iter().zip(&before[c][m]).enumerate() {
                let expected = transform * *b;
                let joint = &mapped.names()[j];
                assert!(
                    same_pose(a, &expected, 2e-5, 1e-4),
                    "{name} {method:?} {joint}: {a:?} against {expected:?}"
                );
            }
        }
    }
}

/// Two seconds into the passive bending the rod has bent: orientation only keeps every bone's
/// length and misses the chest, orientation and position meet the chest and stretch the
/// bones. Off the spine, a joint with a body keeps its offset from the body and any other
/// joint its neutral local transform.
#[test]
fn the_bent_rod_trades_bone_length_for_the_chest_gap() {
    let (start, lab) = (
        lab("rig_passive_bending", 0),
        lab("rig_passive_bending", 120),
    );
    let (spine, mapped) = character(&lab, "rod");
    let orientation = errors(&lab, spine, BoneMethod::Orientation);
    let both = errors(&lab, spine, BoneMethod::OrientationPosition);
    assert!(orientation.length_cm < 1e-3, "{orientation:?}");
    assert!(orientation.chest_gap_cm > 1.0, "{orientation:?}");
    assert!(both.chest_gap_cm < 1e-3, "{both:?}");
    assert!(both.length_cm > 1.0, "{both:?}");
    let rig = Rig::load(format!("{RIGS}/Human.tof")).unwrap();
    let locals = neutral_locals(&hd());
    let ragdoll = lab.ragdolls.iter().find(|r| r.name == "rod").unwrap();
    let body_pose = |lab: &Lab, name: &str| {
        let body = lab.world.body(ragdoll.part(&lab.world, name)?);
        Some(Iso::new(body.position, body.orientation))
    };
    for method in spine.methods().iter().copied() {
        let poses = mapped.pose(&lab.world, method);
        let bones = spine.pose(&lab.world, method);
        for (k, &j) in mapped.chain().iter().enumerate() {
            let bone = Iso::new(bones.origins[k], bones.rotations[k]);
            assert!(
                same_pose(&poses[j], &bone, 1e-6, 1e-6),
                "{method:?} bone {k}: {:?} against {bone:?}",
                poses[j]
            );
        }
        let (mut riding, mut following) = (0, 0);
        for (j, name) in mapped.names().iter().enumerate() {
            if mapped.chain().contains(&j) {
                continue;
            }
            let (posed, expected) = match (rig.part_index(name), mapped.parents()[j]) {
                (Some(_), _) => {
                    riding += 1;
                    let (body_bent, body_start) = (body_pose(&lab, name), body_pose(&start, name));
                    let offset = |body: Iso, pose: Iso| body.inverse() * pose;
                    let posed = offset(body_bent.unwrap(), poses[j]);
                    (posed, offset(body_start.unwrap(), mapped.at_handover()[j]))
                }
                (None, Some(p)) => {
                    following += 1;
                    (poses[p].inverse() * poses[j], locals[j])
                }
                (None, None) => continue,
            };
            assert!(
                same_pose(&posed, &expected, 1e-5, 1e-4),
                "{method:?} {name}: {posed:?} against {expected:?}"
            );
        }
        assert_eq!((riding, following), (18, 46));
        let head = mapped
            .names()
            .iter()
            .position(|n| n == "C_Head_sjnt_0")
            .unwrap();
        let moved = poses[head].translation - mapped.at_handover()[head].translation;
        assert!(moved.length() > 0.1, "the head moved {moved} m");
    }
}

/// The humanoid's skeleton is the general one: [`Skeleton::new`] from the bones' poses and
/// bodies at the transition poses the bones as [`Skeleton::attach`] does, by every method,
/// two seconds into the passive bending.
#[test]
fn the_humanoids_skeleton_is_the_general_one_at_its_own_bones() {
    let path = format!("{}/scenes/passive_bending.toml", env!("CARGO_MANIFEST_DIR"));
    let mut lab = Scene::load(path).unwrap().build().unwrap();
    let general: Vec<Skeleton> = (lab.ragdolls.iter())
        .map(|r| {
            let attached = r.skeleton.as_ref().unwrap();
            let bones = attached.pose(&lab.world, BoneMethod::Rigid);
            let pose = |k: usize| Iso::new(bones.origins[k], bones.rotations[k]);
            let given = std::array::from_fn(|k| (attached.bodies()[k], pose(k)));
            let rod = (r.constraints.clone())
                .find(|&c| matches!(lab.world.constraints[c], Constraint::Rod(_)));
            Skeleton::new(&lab.world, &given, rod).unwrap()
        })
        .collect();
    assert_eq!(general.len(), 2);
    sim::run(&mut lab, 120, &mut NoObserver).unwrap();
    for (ragdoll, general) in lab.ragdolls.iter().zip(&general) {
        let attached = ragdoll.skeleton.as_ref().unwrap();
        assert_eq!(attached.methods(), general.methods());
        for method in ALL_METHODS {
            let (a, b) = (
                attached.pose(&lab.world, method),
                general.pose(&lab.world, method),
            );
            for k in 0..BONES {
                let (a, b) = (
                    Iso::new(a.origins[k], a.rotations[k]),
                    Iso::new(b.origins[k], b.rotations[k]),
                );
                assert!(
                    same_pose(&a, &b, 1e-5, 1e-5),
                    "{} {method:?} {k}: {a:?} {b:?}",
                    ragdoll.name
                );
            }
            let (ea, eb) = (
                errors(&lab, attached, method),
                errors(&lab, general, method),
            );
            assert!((ea.length_cm - eb.length_cm).abs() < 1e-3, "{ea:?} {eb:?}");
            assert!(
                (ea.chest_gap_cm - eb.chest_gap_cm).abs() < 1e-3,
                "{ea:?} {eb:?}"
            );
        }
    }
}
