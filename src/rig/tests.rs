//! Facts about Jolt's Human ragdoll and its animations, the reader's errors, and its
//! behaviour under truncation and mutation.

use super::tof::{Document, Value};
use super::*;
use crate::math::Mat3;

fn path(name: &str) -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    format!("{dir}/scenes/rigs/jolt-human/{name}")
}

fn text(name: &str) -> String {
    std::fs::read_to_string(path(name)).unwrap()
}

fn human() -> Rig {
    Rig::load(path("Human.tof")).unwrap()
}

fn clip(name: &str) -> Animation {
    Animation::load(path(name)).unwrap()
}

const CLIPS: [&str; 4] = [
    "walk.tof",
    "neutral.tof",
    "dead_pose1.tof",
    "dead_pose2.tof",
];

/// `text` with line `line` (1-based) replaced by `with`.
fn replace_line(text: &str, line: usize, with: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[line - 1] = with;
    lines.join("\n")
}

/// Whether two poses agree within `metres` and `radians`.
fn same_pose(a: &Iso, b: &Iso, metres: f32, radians: f32) -> bool {
    a.translation.distance(b.translation) < metres && a.rotation.angle_between(b.rotation) < radians
}

#[test]
fn human_has_23_parts_22_joints_and_its_shapes() {
    let rig = human();
    assert_eq!((rig.parts.len(), rig.constraints.len()), (23, 22));
    assert_eq!(rig.name, "Human");
    let leaves = rig.parts.iter().flat_map(|p| p.shapes.iter());
    let count = |f: fn(&PartShape) -> bool| leaves.clone().filter(|s| f(&s.shape)).count();
    assert_eq!(count(|s| matches!(s, PartShape::Capsule { .. })), 15);
    assert_eq!(count(|s| matches!(s, PartShape::TaperedCapsule { .. })), 8);
    assert_eq!(count(|s| matches!(s, PartShape::Box { .. })), 2);
    // 25 shapes on 23 parts: the two neck parts are two capsules each.
    let doubles = rig.parts.iter().filter(|p| p.shapes.len() == 2);
    let doubles: Vec<&str> = doubles.map(|p| p.joint_name.as_str()).collect();
    assert_eq!(doubles, ["C_Neck_sjnt_1", "C_Neck_sjnt_2"]);
    // The root is the hips; parents come first; the spine chain by parent names.
    assert_eq!(rig.parts[0].joint_name, "hipsBone");
    assert_eq!(rig.parts[0].parent, None);
    let mut rest = rig.parts.iter().enumerate().skip(1);
    assert!(rest.all(|(i, p)| p.parent.is_some_and(|q| q < i)));
    let parent = |name: &str| rig.parts[rig.part_index(name).unwrap()].parent;
    let name = |i: Option<usize>| i.map(|i| rig.parts[i].joint_name.as_str());
    let spine = "hipsBone C_Spine_sjnt_0 C_Spine_sjnt_1 C_Spine_sjnt_2 C_Spine_sjnt_4";
    let spine: Vec<&str> = spine.split(' ').collect();
    for pair in spine.windows(2) {
        assert_eq!(name(parent(pair[1])), Some(pair[0]));
    }
    for p in &rig.parts {
        assert_eq!(p.motion_type, MotionType::Dynamic);
        assert_eq!([p.friction, p.restitution], [1.0, 0.15]);
        assert_eq!(p.gravity_factor, 1.0);
        assert_eq!([p.linear_damping, p.angular_damping], [0.05, 0.05]);
        assert_eq!(p.max_linear_velocity, 500.0);
        assert!((p.max_angular_velocity - 0.25 * std::f32::consts::PI * 60.0).abs() < 1e-4);
        assert!(p.shapes.iter().all(|s| s.density == 1000.0));
    }
    let half_extent = Vec3::new(0.044436, 0.036129, 0.1124695);
    let foot = PartShape::Box {
        half_extent,
        convex_radius: 0.0036129002,
    };
    assert_eq!(rig.parts[3].shapes[0].shape, foot);
}

#[test]
fn joints_join_parent_to_child_at_the_childs_origin() {
    let rig = human();
    let bind = rig.bind_pose();
    for (k, c) in rig.constraints.iter().enumerate() {
        assert_eq!((c.body2, rig.parts[c.body2].parent), (k + 1, Some(c.body1)));
        assert_eq!(c.space, ConstraintSpace::World);
        // World space: both anchors coincide, at the child's joint (its part's origin).
        let [a1, a2] = c.world_anchors(&rig, &bind);
        assert!(a1.distance(a2) < 0.001 && a2.distance(rig.parts[c.body2].position) < 0.001);
        let [f1, f2] = c.body_frames(&rig);
        assert!(f2.0.length() < 0.001, "{k}: {f2:?}");
        assert!(bind[c.body1].transform_point(f1.0).distance(a1) < 1e-5);
        let axes = [
            (c.twist_axis1, c.plane_axis1),
            (c.twist_axis2, c.plane_axis2),
        ];
        for (twist, plane) in axes {
            assert!((twist.length() - 1.0).abs() < 1e-6 && twist.dot(plane).abs() < 1e-3);
        }
        assert!(c.normal_half_cone_angle > 0.0 && c.plane_half_cone_angle > 0.0);
        assert!(c.twist_min_angle < c.twist_max_angle);
        // Knees, clavicles and arms get half the torque of the other joints.
        let name = rig.parts[c.body2].joint_name.as_str();
        let weak = name.contains("Leg_sjnt_1") || name.contains("Clavicle") || name.contains("Arm");
        let torque = if weak { 500.0 } else { 1000.0 };
        for m in [c.swing_motor, c.twist_motor] {
            assert_eq!([m.frequency, m.damping], [20.0, 2.0]);
            assert_eq!(
                [m.min_torque_limit, m.max_torque_limit],
                [-torque, torque],
                "{name}"
            );
            assert_eq!([m.min_force_limit, m.max_force_limit], [f32::MIN, f32::MAX]);
        }
    }
    // The right hip, as the file writes it: a 45 degree cone across, about 34 degrees in the
    // plane, twist within about 33 degrees either way.
    let hip = rig.constraints[0];
    assert!((hip.normal_half_cone_angle - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
    assert_eq!(hip.plane_half_cone_angle, 0.59544647);
    assert_eq!(
        [hip.twist_min_angle, hip.twist_max_angle],
        [-0.578072, 0.578072]
    );
    assert_eq!(hip.max_friction_torque, 5.0);
}

#[test]
fn no_collide_pairs_come_from_the_group_filter_table() {
    let rig = human();
    let name = |i: usize| rig.parts[i].joint_name.as_str();
    // Every parent and child, as Jolt's `DisableParentChildCollisions` sets.
    for (i, p) in rig.parts.iter().enumerate() {
        let pair = p.parent.map(|parent| (parent, i));
        assert!(
            pair.is_none_or(|pair| rig.no_collide.contains(&pair)),
            "{}",
            name(i)
        );
    }
    let others = rig
        .no_collide
        .iter()
        .filter(|&&(a, b)| rig.parts[b].parent != Some(a));
    let mut others: Vec<(&str, &str)> = others.map(|&(a, b)| (name(a), name(b))).collect();
    others.sort();
    let expected = [
        ("C_Neck_sjnt_1", "C_Head_sjnt_0"),
        ("C_Spine_sjnt_4", "C_Neck_sjnt_1"),
        ("L_Clavicle_sjnt_0", "C_Neck_sjnt_0"),
        ("L_Clavicle_sjnt_0", "C_Neck_sjnt_1"),
        ("L_Clavicle_sjnt_0", "R_Clavicle_sjnt_0"),
        ("R_Clavicle_sjnt_0", "C_Neck_sjnt_0"),
        ("R_Clavicle_sjnt_0", "C_Neck_sjnt_1"),
    ];
    assert_eq!(others, expected);
    assert_eq!(rig.no_collide.len(), 29);
    assert!(rig.no_collide.iter().all(|&(a, b)| a < b));
}

#[test]
fn masses_come_from_the_true_shapes() {
    use std::f32::consts::PI;
    let rig = human();
    let total = rig.total_mass();
    assert!((total - 63.80).abs() < 0.05, "{total}");
    // The hips: one capsule, r = 0.105886, h = 0.0730925, density 1000, rotated and offset.
    let (hips, r, h) = (&rig.parts[0], 0.105886f32, 0.0730925f32);
    let mass = 1000.0 * (PI * r * r * 2.0 * h + 4.0 / 3.0 * PI * r * r * r);
    assert!(
        (hips.mass.mass - mass).abs() < 1e-4 * mass,
        "{} {mass}",
        hips.mass.mass
    );
    let s = hips.shapes[0];
    assert!(hips.mass.com.distance(s.position) < 1e-6);
    let rotation = Mat3::from_quat(s.rotation);
    let turned = rotation * mass::capsule(h, r, 1000.0).inertia * rotation.transpose();
    assert!(hips.mass.inertia.abs_diff_eq(turned, 1e-5));
    // A thigh: the exact centre of mass, not Jolt's half way between the ends.
    let thigh = &rig.parts[1];
    let PartShape::TaperedCapsule {
        half_height: h,
        top_radius: a,
        bottom_radius: b,
    } = thigh.shapes[0].shape
    else {
        panic!("the thigh is a tapered capsule")
    };
    let exact = mass::tapered_capsule(h, a, b, 1000.0);
    assert!(exact.com.y - 0.5 * (a - b) > 0.005, "{}", exact.com.y);
    let placed = thigh.shapes[0].position + thigh.shapes[0].rotation * exact.com;
    assert!(thigh.mass.com.distance(placed) < 1e-6);
    // The necks: twice one capsule's mass.
    for name in ["C_Neck_sjnt_1", "C_Neck_sjnt_2"] {
        let p = &rig.parts[rig.part_index(name).unwrap()];
        let one = p.shapes[0].shape.mass_properties(1000.0).mass;
        assert!((p.mass.mass - 2.0 * one).abs() < 1e-5);
    }
    for p in &rig.parts {
        let i = p.mass.inertia;
        assert!(i.abs_diff_eq(i.transpose(), 1e-7), "{}", p.joint_name);
        // Positive definite (leading minors); a diagonal entry is at most the other two's sum.
        let d = [i.x_axis.x, i.y_axis.y, i.z_axis.z];
        let minor = d[0] * d[1] - i.x_axis.y * i.y_axis.x;
        assert!(
            d[0] > 0.0 && minor > 0.0 && i.determinant() > 0.0,
            "{}",
            p.joint_name
        );
        assert!(d[0] <= d[1] + d[2] && d[1] <= d[0] + d[2] && d[2] <= d[0] + d[1]);
    }
}

#[test]
fn every_animation_loads_and_walk_is_keyed_at_30_hz() {
    let rig = human();
    for file in CLIPS {
        let a = clip(file);
        assert_eq!(a.joints.len(), 23, "{file}");
        assert!(a.looping, "no mIsLooping in the file: Jolt's default");
        assert!(a.joints.iter().all(|j| rig.part_index(&j.name).is_some()));
        let keys = if file == "walk.tof" { 85 } else { 1 };
        assert!(a.joints.iter().all(|j| j.keys.len() == keys), "{file}");
    }
    let walk = clip("walk.tof");
    assert_eq!(walk.name, "walk");
    assert!((walk.duration() - 2.8).abs() < 1e-4, "{}", walk.duration());
    for j in &walk.joints {
        for (k, key) in j.keys.iter().enumerate() {
            assert!((key.time - k as f32 / 30.0).abs() < 2e-6, "{} {k}", j.name);
        }
    }
}

#[test]
fn bone_lengths_match_the_rig_at_every_time() {
    let rig = human();
    for file in CLIPS {
        let a = clip(file);
        for time in [0.0, 0.41, 1.0, 1.37, 2.79, 3.5] {
            for (name, translation, _) in a.sample(time) {
                let part = &rig.parts[rig.part_index(name).unwrap()];
                let Some(parent) = part.parent else { continue };
                let bone = part.position.distance(rig.parts[parent].position);
                let len = translation.length();
                assert!(
                    (len - bone).abs() < 0.001,
                    "{file} {time} {name}: {len} vs {bone}"
                );
            }
        }
    }
}

#[test]
fn sampling_interpolates_and_loops_or_clamps() {
    let mut walk = clip("walk.tof");
    let keys = walk.joints[0].keys.clone();
    fn at(a: &Animation, t: f32) -> (&str, Vec3, Quat) {
        a.sample(t)[0]
    }
    let (_, t, r) = at(&walk, keys[7].time);
    assert!(t.distance(keys[7].translation) < 1e-6 && r.angle_between(keys[7].rotation) < 1e-3);
    let (_, t, r) = at(&walk, 0.5 * (keys[7].time + keys[8].time));
    assert!(t.distance(0.5 * (keys[7].translation + keys[8].translation)) < 1e-6);
    let (a1, a2) = (
        r.angle_between(keys[7].rotation),
        r.angle_between(keys[8].rotation),
    );
    assert!(
        (a1 - a2).abs() < 1e-3 && (r.length() - 1.0).abs() < 1e-6,
        "{a1} {a2}"
    );
    // Looping wraps the time by the duration; otherwise the ends hold.
    let (_, t1, _) = at(&walk, 0.9);
    let (_, t2, _) = at(&walk, 0.9 + walk.duration());
    assert!(t1.distance(t2) < 1e-4);
    walk.looping = false;
    let (first, last) = (keys[0], keys[keys.len() - 1]);
    assert_eq!(
        at(&walk, 10.0),
        ("hipsBone", last.translation, last.rotation)
    );
    assert_eq!(
        at(&walk, -1.0),
        ("hipsBone", first.translation, first.rotation)
    );
}

#[test]
fn posing_the_rig_from_animations() {
    let rig = human();
    // The neutral clip is the rig's own pose.
    let neutral = rig.pose(&clip("neutral.tof"), 0.0);
    assert!(neutral
        .iter()
        .zip(rig.bind_pose())
        .all(|(p, q)| same_pose(p, &q, 1e-5, 1e-3)));
    for file in CLIPS {
        let a = clip(file);
        for time in [0.0, 0.3, 1.7] {
            let world = rig.pose(&a, time);
            for (i, p) in rig.parts.iter().enumerate() {
                let Some(parent) = p.parent else { continue };
                let bone = p.position.distance(rig.parts[parent].position);
                let d = world[i].translation.distance(world[parent].translation);
                assert!((d - bone).abs() < 0.001, "{file} {}", p.joint_name);
            }
            let back = rig.world_from_local(&rig.local_from_world(&world));
            assert!(world
                .iter()
                .zip(&back)
                .all(|(w, b)| same_pose(w, b, 1e-5, 1e-3)));
            // The joints hold in every animated pose.
            for c in &rig.constraints {
                let [a1, a2] = c.world_anchors(&rig, &world);
                assert!(a1.distance(a2) < 0.001, "{file} {time}: {}", c.body2);
            }
        }
    }
}

#[test]
fn errors_name_the_file_the_line_and_the_field() {
    let human = text("Human.tof");
    let read = |text: &str| Rig::from_str(text, "Human.tof").unwrap_err();
    let at = |line: usize, field: &str, msg: &str| format!("Human.tof:{line}: {field}: {msg}");
    let cone = "SwingTwistConstraintSettings 00000006 field mNormalHalfConeAngle";
    assert_eq!(human.lines().nth(708), Some("  0.785398006"));
    let truncated: String = human.lines().take(708).map(|l| format!("{l}\n")).collect();
    assert_eq!(read(&truncated), at(708, cone, "unexpected end of file"));
    let abc = read(&replace_line(&human, 709, "  abc"));
    assert_eq!(abc, at(709, cone, "expected a float, got \"abc\""));
    // A field inside an inline instance: the part's friction and motion type.
    let doc = Document::parse(&human, "Human.tof").unwrap();
    let Value::Object(part3) = &doc.root().unwrap().array("mParts").unwrap()[3] else {
        panic!("parts are inline")
    };
    let line_of = |name: &str| part3.fields.iter().find(|f| f.name == name).unwrap().line;
    let (friction, motion) = (line_of("mFriction"), line_of("mMotionType"));
    let part = "RagdollSettings 00000001 field mParts[3]";
    let err = read(&replace_line(&human, friction, "1.x"));
    let msg = "expected a float, got \"1.x\"";
    assert_eq!(err, at(friction, &format!("{part}.mFriction"), msg));
    let err = read(&replace_line(&human, motion, "7"));
    let msg = "unknown motion type 7";
    assert_eq!(err, at(motion, &format!("{part}.mMotionType"), msg));
    // A reference to an object the file lacks, and an unknown type.
    assert_eq!(human.lines().nth(623), Some("      00000031"));
    let field = "StaticCompoundShapeSettings 00000003 field mSubShapes[0].mShape";
    let err = read(&replace_line(&human, 624, "000000FF"));
    assert_eq!(err, at(624, field, "no object has the id 000000FF"));
    let err = read(&human.replacen("mFriction float", "mFriction flaot", 1));
    let field = "declare RagdollSettings::Part field mFriction";
    assert_eq!(err, at(20, field, "unknown type \"flaot\""));
    let walk = replace_line(&text("walk.tof"), 27, "  -1");
    let err = Animation::from_str(&walk, "walk.tof").unwrap_err();
    let field = "SkeletalAnimation 00000001 field mAnimatedJoints[0].mKeyframes[2].mTime";
    assert_eq!(err, format!("walk.tof:27: {field}: key times go back"));
}

#[test]
fn the_reader_resolves_forward_ids_strings_and_inline_instances() {
    let text = "TOS 1.00\n\
        declare Node 4\n mName string\n mNext pointer Node\n\
        mValues array float\n mPair instance Pair\n\
        declare Pair 2\n mA uint8\n mB bool\n\
        object Node 00000001\n \"a \\\"quoted\\\"\\\\ name\\n\"\n\
        00000002\n 3 1.5 -2 3e2\n 255 true\n\
        object Node 00000002\n \"b\" 00000000 0 0 false\n";
    let doc = Document::parse(text, "t.tof").unwrap();
    let first = doc.root().unwrap();
    assert_eq!(first.string("mName").unwrap(), "a \"quoted\"\\ name\n");
    let values = [Value::Float(1.5), Value::Float(-2.0), Value::Float(300.0)];
    assert_eq!(first.array("mValues").unwrap(), values);
    let pair = first.inline("mPair").unwrap();
    assert_eq!(pair.uint("mA").unwrap(), 255);
    assert!(pair.boolean("mB").unwrap());
    let second = first.reference("mNext").unwrap().unwrap();
    assert_eq!((second.obj.id, second.obj.line), (Some(2), 15));
    assert!(second.reference("mNext").unwrap().is_none());
    let err = first.float("mName").unwrap_err();
    assert_eq!(err, "t.tof:11: Node 00000001 field mName: expected a float");
    let err = Document::parse(&text.replace("255", "256"), "t.tof").unwrap_err();
    let node = "t.tof:14: Node 00000001 field";
    assert_eq!(
        err,
        format!("{node} mPair.mA: expected an integer, got \"256\"")
    );
    let dangling = text.replace("00000002\n 3", "00000003\n 3");
    let err = Document::parse(&dangling, "t.tof").unwrap_err();
    assert_eq!(
        err,
        "t.tof:12: Node 00000001 field mNext: no object has the id 00000003"
    );
    let looped = "TOS 1.00 declare A 1 a instance A object A 1";
    assert!(Document::parse(looped, "l.tof")
        .unwrap_err()
        .contains("nesting too deep"));
}

/// A tiny deterministic generator (xorshift64).
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Runs `read` on `text`; fails the test if it panics, or if its error does not begin with
/// `file:line:`. Whether it read the text.
fn no_panic(
    file: &str,
    case: &str,
    text: &[u8],
    read: fn(&str, &str) -> Result<(), String>,
) -> bool {
    let text = String::from_utf8_lossy(text).into_owned();
    let result = std::panic::catch_unwind(|| read(&text, file));
    let Ok(result) = result else {
        panic!("{case} panicked")
    };
    let line = |e: &String| e.strip_prefix(file)?.strip_prefix(':')?.chars().next();
    let at_line = |e: &String| line(e).is_some_and(|c| c.is_ascii_digit());
    assert!(
        result.as_ref().err().is_none_or(at_line),
        "{case}: {result:?}"
    );
    result.is_ok()
}

#[test]
fn truncations_and_mutations_give_errors_not_panics() {
    let rig: fn(&str, &str) -> Result<(), String> = |t, file| Rig::from_str(t, file).map(drop);
    let clip: fn(&str, &str) -> Result<(), String> =
        |t, file| Animation::from_str(t, file).map(drop);
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    for (file, read, mutants) in [("Human.tof", rig, 800), ("neutral.tof", clip, 300)] {
        let bytes = text(file).into_bytes();
        assert!(no_panic(file, file, &bytes, read));
        let cuts = (0..bytes.len()).step_by(7);
        let parsed =
            cuts.filter(|&n| no_panic(file, &format!("{file} cut at {n}"), &bytes[..n], read));
        // Only cuts inside the last number can still parse.
        assert!(parsed.count() <= 2, "{file}");
        let nasty = b" \n\"\\-+.0123456789eE-xX0Finfnan";
        let mut errors = 0;
        for m in 0..mutants {
            let mut b = bytes.clone();
            for _ in 0..1 + rng.below(3) {
                let i = rng.below(b.len());
                match rng.below(4) {
                    0 => b[i] = nasty[rng.below(nasty.len())],
                    1 => b[i] = rng.next() as u8,
                    2 => drop(b.remove(i)),
                    _ => b.insert(i, nasty[rng.below(nasty.len())]),
                }
            }
            errors += usize::from(!no_panic(file, &format!("{file} mutant {m}"), &b, read));
        }
        // Most mutants break the file (Human.tof: 702 of 800; neutral.tof: 243 of 300).
        assert!(errors > mutants / 2, "{file}: {errors} errors of {mutants}");
    }
}
