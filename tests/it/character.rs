//! Game characters from a shipped rig (`[[character]]`, Horizon Zero Dawn's ragdoll as Jolt
//! Physics ships it): built at a clip's pose, stable under gravity, and the paper's simplified
//! ragdoll beside the rig's own spine.

use rodlab::body::BodyKind;
use rodlab::math::Iso;
use rodlab::rig::{Animation, Rig};
use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver};
use rodlab::skeleton::BoneMethod;

const RIGS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/rigs/jolt-human");
const BENDING: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenes/rig_passive_bending.toml"
);

/// A scene of one character at `spine`, hips fixed, standing in the neutral clip.
fn standing(spine: &str, extra: &str) -> Scene {
    let text = format!(
        "method = \"paper\"\nframes = 600\n[[character]]\nname = \"c\"\n\
         rig = \"{RIGS}/Human.tof\"\nclip = \"{RIGS}/neutral.tof\"\nspine = \"{spine}\"\n\
         region = {{ from = \"hipsBone\", to = \"C_Spine_sjnt_4\" }}\nfixed = [\"hipsBone\"]\n{extra}"
    );
    Scene::parse("/c.toml", &text).unwrap()
}

/// Built at the clip's pose: every body's part frame is where the clip puts the part; the
/// rig's spine keeps all 23 parts and 22 joints, the rod spine drops the three between hips and
/// chest and their four joints for one rod, and both weigh what the rig does.
#[test]
fn a_character_is_built_at_its_clips_pose_with_the_rigs_mass() {
    let rig = Rig::load(format!("{RIGS}/Human.tof")).unwrap();
    let clip = Animation::load(format!("{RIGS}/neutral.tof")).unwrap();
    let posed: Vec<Iso> = rig.pose(&clip, 0.0);
    for (spine, bodies, joints, rods) in [
        ("rig", 23, 22, 0),
        ("rod", 20, 18, 1),
        ("single", 20, 19, 0),
    ] {
        let lab = standing(spine, "").build().unwrap();
        let world = &lab.world;
        assert_eq!(world.bodies.len(), bodies, "{spine}");
        let rod_count = world.rod_states().count();
        assert_eq!(
            (world.constraints.len() - rod_count, rod_count),
            (joints, rods),
            "{spine}"
        );
        let mass: f32 = world.bodies.iter().map(|b| b.mass).sum();
        assert!((mass - rig.total_mass()).abs() < 1e-3, "{spine}: {mass} kg");
        for b in &world.bodies {
            let part = rig.part_index(b.name.trim_start_matches("c/")).unwrap();
            let p = &rig.parts[part];
            // the body sits at the part's centre of mass, turned as its first shape
            let expected = posed[part] * Iso::new(p.mass.com, p.shapes[0].rotation);
            let moved = (b.position - expected.translation).length();
            assert!(moved < 1e-5, "{spine} {}: {moved} m off", b.name);
            assert!(
                b.orientation.dot(expected.rotation).abs() > 1.0 - 1e-6,
                "{}",
                b.name
            );
        }
        let fixed: Vec<&str> = (world.bodies.iter())
            .filter(|b| b.kind == BodyKind::Fixed)
            .map(|b| b.name.as_str())
            .collect();
        assert_eq!(fixed, ["c/hipsBone"]);
    }
}

/// The §6 handover from a walk: 1 s into the clip every body is where the clip puts its part
/// and moves as the clip does there, its velocity the clip's finite difference over one
/// keyframe (the centre of mass's within 3 cm/s of walking speeds of 1.5 m/s, the turn's within
/// 0.01 rad/s).
#[test]
fn a_character_handed_over_from_a_walk_moves_as_the_clip_does() {
    let scene = standing("rod", "").text.replace("neutral.tof", "walk.tof");
    let scene = scene.replace("fixed = [\"hipsBone\"]", "time = 1.0");
    let lab = Scene::parse("/c.toml", &scene).unwrap().build().unwrap();
    let rig = Rig::load(format!("{RIGS}/Human.tof")).unwrap();
    let walk = Animation::load(format!("{RIGS}/walk.tof")).unwrap();
    let span = rodlab::scene::HANDOVER_SPAN;
    let [before, now, after] =
        [1.0 - span / 2.0, 1.0, 1.0 + span / 2.0].map(|t| rig.pose(&walk, t));
    let mut fastest = 0.0f32;
    for b in &lab.world.bodies {
        let part = rig.part_index(b.name.trim_start_matches("c/")).unwrap();
        let p = &rig.parts[part];
        let com = |pose: &[Iso]| pose[part].transform_point(p.mass.com);
        assert!((b.position - com(&now)).length() < 1e-5, "{}", b.name);
        let expected = (com(&after) - com(&before)) / span;
        fastest = fastest.max(expected.length());
        let off = (b.linear_velocity - expected).length();
        assert!(
            off < 0.03,
            "{}: {} against {expected} m/s",
            b.name,
            b.linear_velocity
        );
        let turn = after[part].rotation * before[part].rotation.inverse();
        let spin = rodlab::math::rotation_vector(turn.normalize()) / span;
        assert!((b.angular_velocity - spin).length() < 0.01, "{}", b.name);
    }
    assert!(fastest > 1.0, "the walk hands over {fastest} m/s at most");
}

/// Standing in the neutral pose under gravity, hips fixed, for 10 s at the paper's method: the
/// upper body folds forward onto its joint limits and the limbs swing below it (nothing damps
/// them in the paper's method), without an explosion or a gain of energy, every joint held
/// (under 10 cm at worst, 3 cm on average, at 20 iterations of the cheap joint), for the rig's
/// spine and the rod.
#[test]
fn the_rig_hangs_from_its_fixed_hips_for_ten_seconds_at_the_papers_method() {
    for spine in ["rig", "rod"] {
        let scene = standing(spine, "");
        let mut lab = scene.build().unwrap();
        let report = sim::run(&mut lab, 600, &mut NoObserver).unwrap();
        assert_eq!(report.frames, 600, "{spine}");
        let s = report.ragdolls[0].summary;
        let kinetic = lab.world.kinetic_energy();
        eprintln!(
            "{spine}: dislocation max {} cm, mean {} cm; energy {} -> {} J, kinetic at the end {kinetic} J",
            s.dislocation_max,
            s.mean_dislocation_cm(),
            report.initial_energy,
            report.final_energy
        );
        assert!(
            s.dislocation_max < 10.0 && s.mean_dislocation_cm() < 3.0,
            "{spine}"
        );
        assert!(report.final_energy < report.initial_energy, "{spine}");
    }
}

/// Passive bending on the real rig (Fig. 2, top of Fig. 8), both spines slumping about as far:
/// at the paper's 20 iterations the spine's own residual, the rod's against the rig's four
/// spine joints', is under a tenth, and the rod character's mean dislocation over all its
/// joints is lower too, though not by as much: the limbs and neck, the same in both, leave
/// most of it (the clavicles, 0.9 kg between a 5 kg chest and a 2 kg arm, the most).
#[test]
fn the_rod_character_leaves_less_residual_than_the_rigs_spine_in_passive_bending() {
    let scene = Scene::load(BENDING).unwrap();
    let mut lab = scene.build().unwrap();
    let frames = scene.def.frames;
    let (mut rig_spine, mut rod_spine) = (0.0f64, 0.0f64);
    for _ in 0..frames {
        lab.step().unwrap();
        for c in &lab.world.constraints {
            let cm = 100.0 * c.dislocation(&lab.world.bodies) as f64 / frames as f64;
            match c.name() {
                n if n.starts_with("rig/C_Spine_sjnt_") => rig_spine += cm,
                "rod/spine_rod" => rod_spine += cm,
                _ => {}
            }
        }
    }
    assert!(
        rod_spine < 0.1 * rig_spine,
        "spine: rod {rod_spine} cm against the rig's four joints' {rig_spine} cm"
    );
    let mut lab = scene.build().unwrap();
    let report = sim::run(&mut lab, frames, &mut NoObserver).unwrap();
    let mean = |name: &str| {
        let r = report.ragdolls.iter().find(|r| r.name == name).unwrap();
        r.summary.mean_dislocation_cm()
    };
    let (rig, rod) = (mean("rig"), mean("rod"));
    eprintln!(
        "all joints: rig {rig} cm, rod {rod} cm; spine: rig {rig_spine} cm, rod {rod_spine} cm"
    );
    assert!(
        rod < 0.8 * rig,
        "rod {rod} cm against the rig spine's {rig} cm"
    );
}

/// A character's mistakes name the scene's line and field: an unknown part, a region that is
/// not a chain, a rig file that is not there.
#[test]
fn character_mistakes_name_their_field() {
    let cases = [
        (
            "fixed = [\"hipsBone\"]",
            "fixed = [\"tail\"]",
            "character[0].fixed",
            "no part \"tail\"",
        ),
        (
            "from = \"hipsBone\"",
            "from = \"L_Leg_sjnt_0\"",
            "character[0].spine",
            "is not an ancestor",
        ),
        (
            "to = \"C_Spine_sjnt_4\"",
            "to = \"C_Spine_sjnt_0\"",
            "character[0].spine",
            "no part between",
        ),
        ("Human.tof", "Nobody.tof", "character[0].rig", "Nobody.tof"),
    ];
    for (from, to, field, words) in cases {
        let scene = standing("rod", "");
        let text = scene.text.replacen(from, to, 1);
        let e = match Scene::parse("/c.toml", &text).map(|s| s.build()) {
            Ok(Ok(_)) => panic!("{to}: built"),
            Ok(Err(e)) => e.to_string(),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(field) && e.contains(words), "{to}: {e}");
    }
}

/// A `[drop]` with a `character` table makes `[[character]]`s as it makes humanoids: one per
/// layout slot, named in order, the clips taken in turn, laid out by the seed; `--spine` and a
/// variant's spine reach them; a humanoid's spine is turned away from a character and a
/// character's from a humanoid, naming the field.
#[test]
fn a_drop_of_characters_is_laid_out_as_a_drop_of_humanoids() {
    let text = |spine: &str, seed: u64| {
        format!(
            "method = \"paper\"\nframes = 10\ncontacts = true\n[drop]\ncount = 6\nspine = \"{spine}\"\n\
             first = [0.0, 1.0, 0.0]\nspacing = [3.0, 0.6, 3.0]\ncolumns = 2\nrows = 1\nseed = {seed}\n\
             character = {{ rig = \"{RIGS}/Human.tof\", clips = [\"{RIGS}/dead_pose1.tof\", \
             \"{RIGS}/dead_pose2.tof\"], region = {{ from = \"hipsBone\", to = \"C_Spine_sjnt_4\" }} }}\n\
             [[body]]\nname = \"floor\"\nkind = \"fixed\"\nshape = \"plane\"\n"
        )
    };
    let scene = Scene::parse("/d.toml", &text("rig", 3)).unwrap();
    let d = &scene.def;
    assert!(d.ragdoll.is_empty());
    let names: Vec<&str> = d.character.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        ["drop000", "drop001", "drop002", "drop003", "drop004", "drop005"]
    );
    for (i, c) in d.character.iter().enumerate() {
        let clip = c.clip.as_deref().unwrap();
        assert!(
            clip.ends_with(["dead_pose1.tof", "dead_pose2.tof"][i % 2]),
            "{clip}"
        );
        // two per layer, layers 0.6 m apart
        assert_eq!(c.position[1], 1.0 + 0.6 * (i / 2) as f32);
    }
    let other_seed = Scene::parse("/d.toml", &text("rig", 4)).unwrap();
    assert_ne!(
        d.character[0].rotation,
        other_seed.def.character[0].rotation
    );
    let lab = scene.build().unwrap();
    assert_eq!(lab.ragdolls.len(), 6);
    assert_eq!(lab.world.bodies.len(), 6 * 23 + 1);
    let mut rod = scene.clone();
    let overrides = sim::Overrides {
        spine: Some(rodlab::ragdoll::SpineKind::Rod),
        seed: Some(4),
        ..Default::default()
    };
    overrides.apply(&mut rod.def);
    assert_eq!(
        rod.def.character[0].rotation,
        other_seed.def.character[0].rotation
    );
    let lab = rod.build().unwrap();
    assert_eq!(lab.world.bodies.len(), 6 * 20 + 1);
    let chain3 = sim::Overrides {
        spine: Some(rodlab::ragdoll::SpineKind::Chain3),
        ..Default::default()
    };
    let mut wrong = scene.clone();
    chain3.apply(&mut wrong.def);
    let e = chain3.check_on(&wrong).unwrap_err();
    assert!(
        e.contains("--spine") && e.contains("rig, rod or single"),
        "{e}"
    );
    let e = Scene::parse("/d.toml", &text("chain3", 3))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("d.toml:6: drop.spine") && e.contains("chain3"),
        "{e}"
    );
    let humanoid = "method = \"paper\"\n[[ragdoll]]\nname = \"h\"\nspine = \"rig\"\n";
    let e = Scene::parse("/h.toml", humanoid).unwrap_err().to_string();
    assert!(
        e.contains("ragdoll[0].spine") && e.contains("h.toml:4"),
        "{e}"
    );
}

/// `play_from`: the clip plays on kinematic bodies from `play_from` to the handover `time`,
/// each frame's step carrying every body to where the clip has it a frame later (within 1 mm
/// and 0.01 rad); at the handover frame the bodies turn dynamic at the clip's pose with its
/// velocities, exactly as a character handed over at the first frame starts.
#[test]
fn a_clip_plays_kinematically_until_the_handover_then_physics_takes_over() {
    let text = standing("rod", "").text.replace("neutral.tof", "walk.tof");
    let handed = text.replace("fixed = [\"hipsBone\"]", "time = 1.0");
    let played = text.replace("fixed = [\"hipsBone\"]", "time = 1.0\nplay_from = 0.5");
    let at_once = Scene::parse("/c.toml", &handed).unwrap().build().unwrap();
    let scene = Scene::parse("/c.toml", &played).unwrap();
    let mut lab = scene.build().unwrap();
    let rig = Rig::load(format!("{RIGS}/Human.tof")).unwrap();
    let walk = Animation::load(format!("{RIGS}/walk.tof")).unwrap();
    let dt = scene.def.dt;
    let handover = (0.5 / dt).round() as usize;
    assert_eq!(lab.playbacks[0].handover_frame(), handover);
    // each body's centre and orientation as the clip has them at `t` (the body's turn from its
    // part as built at the handover)
    let com = |k: usize, t: f32| {
        let b = &at_once.world.bodies[k];
        let part = rig.part_index(b.name.trim_start_matches("c/")).unwrap();
        let built = rig.pose(&walk, 1.0)[part].rotation.inverse() * b.orientation;
        let pose = rig.pose(&walk, t)[part];
        (
            pose.transform_point(rig.parts[part].mass.com),
            pose.rotation * built,
        )
    };
    for frame in 0..handover {
        assert!(
            lab.world.bodies.iter().all(|b| !b.is_dynamic()),
            "frame {frame}"
        );
        lab.step().unwrap();
        let t = 1.0 - (handover - frame - 1) as f32 * dt;
        for (k, b) in lab.world.bodies.iter().enumerate() {
            let (position, rotation) = com(k, t);
            let off = (b.position - position).length();
            assert!(
                off < 1e-3,
                "frame {frame}, {}: {off} m from the clip",
                b.name
            );
            let turn = rodlab::math::rotation_vector(b.orientation * rotation.inverse());
            assert!(turn.length() < 0.01, "frame {frame}, {}: {turn}", b.name);
        }
    }
    // the handover frame's step starts from the bodies as a handover at the first frame builds
    // them
    let mut first = lab.clone();
    first.playbacks[0].pose(&mut first.world);
    for (b, a) in first.world.bodies.iter().zip(&at_once.world.bodies) {
        assert!(b.is_dynamic(), "{}", b.name);
        assert!((b.position - a.position).length() < 1e-5, "{}", b.name);
        assert!(
            (b.linear_velocity - a.linear_velocity).length() < 1e-5,
            "{}",
            b.name
        );
        assert!(
            (b.angular_velocity - a.angular_velocity).length() < 1e-5,
            "{}",
            b.name
        );
    }
    lab.step().unwrap();
    assert!(lab.world.bodies.iter().all(|b| b.is_dynamic()));
}

/// §6 on the game's animation skeleton: after the handover the rig's spine bones follow their
/// bodies, and with the rod the paper's two interpolations trade errors as the paper says:
/// orientation alone keeps every bone's length and misses the chest, orientation and position
/// meets the chest and stretches the bones. Prints each method's errors (length change, chest
/// gap; cm) at two times after the handover in both rig scenes.
#[test]
fn the_bone_methods_pose_the_games_spine_as_section_6_describes() {
    let scenes = [
        ("rig_walk_to_ragdoll", [0.5, 5.0]),
        ("rig_passive_bending", [2.0, 6.0]),
    ];
    for (name, times) in scenes {
        let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let scene = Scene::load(&path).unwrap();
        let mut lab = scene.build().unwrap();
        let handover = lab.playbacks.first().map_or(0, |p| p.handover_frame());
        let frames_after = times.map(|t| (t / scene.def.dt).round() as usize);
        let mut frame = 0;
        for (t, after) in times.iter().zip(frames_after) {
            while frame < handover + after {
                lab.step().unwrap();
                frame += 1;
            }
            let mut row = format!("| `{name}`, {t} s |");
            for ragdoll in &lab.ragdolls {
                let skeleton = ragdoll
                    .skeleton
                    .as_ref()
                    .expect("the scene names a skeleton");
                assert!(ragdoll.hd_skeleton.is_some(), "{}", ragdoll.name);
                for &method in skeleton.methods() {
                    let e = skeleton.error(&lab.world, &skeleton.pose(&lab.world, method));
                    row += &format!(" {:.2}, {:.2} |", e.length_cm, e.chest_gap_cm);
                    match method {
                        BoneMethod::Rigid => assert!(e.chest_gap_cm < 1e-3, "{row}"),
                        BoneMethod::Orientation => {
                            assert!(e.length_cm < 1e-2 && e.chest_gap_cm > 0.1, "{row}")
                        }
                        BoneMethod::OrientationPosition => {
                            assert!(e.chest_gap_cm < 1e-2 && e.length_cm > 0.1, "{row}")
                        }
                        BoneMethod::Arc => assert!(e.length_cm < 5.0, "{row}"),
                    }
                }
            }
            eprintln!("{row}");
        }
    }
}

/// The scene's two keys come together; a broken file, a pose without every joint and a
/// region whose chain is not a spine are errors naming the key and its line, a region that
/// is no chain of the rig an error of the spine, as without a skeleton.
#[test]
fn scene_errors_name_the_skeleton_keys_and_their_lines() {
    let scene = |keys: &str, region: &str| {
        let text = format!(
            "[[character]]\nname = \"c\"\nrig = \"{RIGS}/Human.tof\"\n\
             region = {{ from = \"{region}\", to = \"C_Spine_sjnt_4\" }}\n{keys}"
        );
        Scene::parse("/c.toml", &text)
            .unwrap()
            .build()
            .map(|_| ())
            .unwrap_err()
    };
    let skeleton = format!("skeleton = \"{RIGS}/skeleton_hd.tof\"\n");
    let pose = format!("skeleton_pose = \"{RIGS}/neutral_hd.tof\"\n");
    let cases = [
        (skeleton.clone(), "hipsBone", "skeleton", 5, "skeleton_pose"),
        (pose.clone(), "hipsBone", "skeleton_pose", 5, "skeleton"),
        (
            format!("skeleton = \"{RIGS}/none.tof\"\n{pose}"),
            "hipsBone",
            "skeleton",
            5,
            "none.tof",
        ),
        (
            format!("{skeleton}skeleton_pose = \"{RIGS}/neutral.tof\"\n"),
            "hipsBone",
            "skeleton_pose",
            6,
            "\"rootBone\"",
        ),
        (
            format!("{skeleton}{pose}"),
            "C_Spine_sjnt_0",
            "skeleton",
            5,
            "has 5 joints",
        ),
        (
            format!("spine = \"rod\"\n{skeleton}{pose}"),
            "L_Leg_sjnt_0",
            "spine",
            5,
            "is not an ancestor",
        ),
    ];
    for (keys, region, field, line, message) in cases {
        let error = scene(&keys, region);
        assert_eq!(error.field, format!("character[0].{field}"), "{error}");
        assert_eq!(error.line, line, "{error}");
        assert!(error.message.contains(message), "{error}");
    }
}
