//! Every scene-file mistake gives an error naming the file, the line and the field.

use rodlab::scene::Scene;

const GOOD: &str = r#"
dt = 0.01
iterations = 10
frames = 10

[[ragdoll]]
name = "r0"
spine = "chain3"

[[body]]
name = "ground"
kind = "fixed"
shape = "box"
half_extents = [1.0, 0.1, 1.0]

[[body]]
name = "ball"
shape = "sphere"
radius = 0.1
mass = 1.0
position = [0.0, 1.0, 0.0]

[[joint]]
name = "tether"
a = "ground"
b = "ball"
anchor = [0.0, 0.5, 0.0]
spring = 0.5
"#;

/// Replaces `from` with `to` in the good scene and returns the error text.
fn error_for(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "test setup: {from:?} not in scene");
    let text = GOOD.replacen(from, to, 1);
    let err = Scene::parse("scenes/x.toml", &text)
        .and_then(|s| s.build().map(|_| ()))
        .expect_err("must fail");
    err.to_string()
}

fn line_of(needle: &str) -> usize {
    GOOD.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn the_good_scene_loads() {
    let scene = Scene::parse("scenes/x.toml", GOOD).unwrap();
    let lab = scene.build().unwrap();
    // the ragdoll, and the group of the scene's own bodies with its joints and rods
    let names: Vec<&str> = lab.ragdolls.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names.len(), 2, "{names:?}");
    assert_eq!(names[1], rodlab::scene::LOOSE_GROUP);
}

#[test]
fn unknown_spine_names_the_field_and_choices() {
    let e = error_for(r#"spine = "chain3""#, r#"spine = "chian3""#);
    let line = line_of("spine =");
    assert!(
        e.starts_with(&format!("scenes/x.toml:{line}: ragdoll[0].spine: ")),
        "{e}"
    );
    assert!(
        e.contains("\"chian3\"") && e.contains("chain3, rig, rod, single"),
        "{e}"
    );
}

#[test]
fn unknown_self_contacts_names_the_field_and_choices() {
    let e = error_for(
        r#"spine = "chain3""#,
        "spine = \"chain3\"\nself_contacts = \"some\"",
    );
    let line = line_of("spine =") + 1;
    assert!(
        e.starts_with(&format!("scenes/x.toml:{line}: ragdoll[0].self_contacts: ")),
        "{e}"
    );
    assert!(
        e.contains("\"some\"") && e.contains("all, apart_at_rest, none"),
        "{e}"
    );
}

#[test]
fn non_positive_mass_on_dynamic_body() {
    let e = error_for("mass = 1.0", "mass = 0.0");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: body[1].mass: ",
            line_of("mass =")
        )),
        "{e}"
    );
    assert!(e.contains("positive"), "{e}");
}

#[test]
fn non_positive_dt() {
    let e = error_for("dt = 0.01", "dt = -0.01");
    assert!(e.starts_with("scenes/x.toml:2: dt: "), "{e}");
}

#[test]
fn zero_iterations() {
    let e = error_for("iterations = 10", "iterations = 0");
    assert!(e.starts_with("scenes/x.toml:3: iterations: "), "{e}");
}

#[test]
fn zero_substeps() {
    let e = error_for("iterations = 10", "iterations = 10\nsubsteps = 0");
    assert_eq!(
        e,
        "scenes/x.toml:4: substeps: must be a whole number from 1 to 1000, got 0"
    );
}

#[test]
fn non_positive_or_nan_push_speed() {
    for bad in ["0.0", "-3.0", "nan"] {
        let e = error_for(
            "iterations = 10",
            &format!("iterations = 10\ncontact_push_speed = {bad}"),
        );
        assert!(
            e.starts_with("scenes/x.toml:4: contact_push_speed: must be positive, or inf (m/s)"),
            "{e}"
        );
    }
}

#[test]
fn warm_start_outside_zero_to_one() {
    for bad in ["-0.1", "1.5", "nan"] {
        let e = error_for(
            "iterations = 10",
            &format!("iterations = 10\ncontact_warm_start = {bad}"),
        );
        assert!(
            e.starts_with("scenes/x.toml:4: contact_warm_start: must be from 0 to 1"),
            "{e}"
        );
    }
}

#[test]
fn negative_or_infinite_contact_softness() {
    for (key, bad, message) in [
        ("contact_hertz", "-1.0", "must be 0 or more (Hz)"),
        ("contact_hertz", "inf", "must be 0 or more (Hz)"),
        ("contact_damping_ratio", "-0.5", "must be 0 or more"),
        ("contact_damping_ratio", "nan", "must be 0 or more"),
        (
            "contact_stacking_max_ratio",
            "0.5",
            "must be 1 or more, or inf",
        ),
    ] {
        let e = error_for(
            "iterations = 10",
            &format!("iterations = 10\n{key} = {bad}"),
        );
        assert!(
            e.starts_with(&format!("scenes/x.toml:4: {key}: {message}")),
            "{e}"
        );
    }
}

#[test]
fn sleep_and_push_speed_reach_the_settings() {
    let default = Scene::parse("scenes/x.toml", GOOD)
        .unwrap()
        .build()
        .unwrap()
        .world;
    assert!(!default.settings.sleep);
    assert_eq!(default.settings.contact_push_speed, f32::INFINITY);
    assert_eq!(default.settings.contact_warm_start, 0.0);
    assert_eq!(default.settings.contact_hertz, 0.0);
    assert_eq!(default.settings.contact_stacking_max_ratio, f32::INFINITY);
    let text = GOOD.replacen(
        "iterations = 10",
        "iterations = 10\nsleep = true\ncontact_push_speed = 3.0\ncontact_warm_start = 0.25\n\
         contact_hertz = 30.0\ncontact_damping_ratio = 0.5\ncontact_stacking_max_ratio = 3.0",
        1,
    );
    let world = Scene::parse("scenes/x.toml", &text)
        .unwrap()
        .build()
        .unwrap()
        .world;
    assert!(world.settings.sleep);
    assert_eq!(world.settings.contact_push_speed, 3.0);
    assert_eq!(world.settings.contact_warm_start, 0.25);
    assert_eq!(world.settings.contact_hertz, 30.0);
    assert_eq!(world.settings.contact_damping_ratio, 0.5);
    assert_eq!(world.settings.contact_stacking_max_ratio, 3.0);
}

#[test]
fn unknown_solver_names_the_choices() {
    let e = error_for("iterations = 10", "iterations = 10\nsolver = \"gpu\"");
    assert!(e.starts_with("scenes/x.toml:4: solver: "), "{e}");
    assert!(
        e.contains("\"gpu\"") && e.contains("scalar") && e.contains("simd"),
        "{e}"
    );
}

#[test]
fn substeps_and_solver_reach_the_settings() {
    use rodlab::world::SolverKind;
    let default = Scene::parse("scenes/x.toml", GOOD)
        .unwrap()
        .build()
        .unwrap()
        .world;
    assert_eq!(default.settings.substeps, 1);
    assert_eq!(default.settings.solver, SolverKind::Scalar);
    let text = GOOD.replacen(
        "iterations = 10",
        "iterations = 10\nsubsteps = 4\nsolver = \"simd\"",
        1,
    );
    let world = Scene::parse("scenes/x.toml", &text)
        .unwrap()
        .build()
        .unwrap()
        .world;
    assert_eq!(world.settings.substeps, 4);
    assert_eq!(world.settings.solver, SolverKind::Simd);
}

#[test]
fn unknown_body_in_a_joint() {
    let e = error_for(r#"b = "ball""#, r#"b = "bal""#);
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: joint[0].b: ",
            line_of(r#"b = "ball""#)
        )),
        "{e}"
    );
    assert!(e.contains("unknown body \"bal\""), "{e}");
}

#[test]
fn relaxation_outside_unit_interval() {
    let e = error_for("spring = 0.5", "spring = 1.5");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: joint[0].spring: ",
            line_of("spring =")
        )),
        "{e}"
    );
    assert!(e.contains("[0, 1]"), "{e}");
}

#[test]
fn unknown_field_is_refused() {
    let e = error_for("radius = 0.1", "radius = 0.1\nradiuss = 0.2");
    assert!(
        e.contains("scenes/x.toml:") && e.contains("body[1]") && e.contains("radiuss"),
        "{e}"
    );
}

#[test]
fn wrong_type_names_the_field() {
    let e = error_for("frames = 10", r#"frames = "ten""#);
    assert!(e.starts_with("scenes/x.toml:4: frames: "), "{e}");
}

#[test]
fn missing_shape_size_names_the_body() {
    let e = error_for("radius = 0.1\n", "");
    assert!(
        e.contains("body[1].radius") && e.contains("required"),
        "{e}"
    );
}

#[test]
fn unknown_pose_joint() {
    let e = error_for(
        r#"spine = "chain3""#,
        "spine = \"chain3\"\npose = { elbw_l = [10.0, 0.0, 0.0] }",
    );
    assert!(
        e.contains("ragdoll[0].pose.elbw_l") && e.contains("elbow_l"),
        "{e}"
    );
}

#[test]
fn broken_toml_names_the_line() {
    let e = error_for("frames = 10", "frames = = 10");
    assert!(e.starts_with("scenes/x.toml:4: "), "{e}");
}

const WITH_ROD: &str = r#"
[[rod]]
name = "spring"
a = "ground"
b = "ball"
rest_length = 0.5
alpha_b = 0.1
"#;

#[test]
fn a_rod_between_bodies_loads() {
    let scene = Scene::parse("scenes/x.toml", &format!("{GOOD}{WITH_ROD}")).unwrap();
    let world = scene.build().unwrap().world;
    assert!(world.constraints.iter().any(|c| c.name() == "spring"));
}

#[test]
fn zero_or_negative_rest_length_is_refused() {
    for bad in ["0.0", "-0.2"] {
        let text = format!(
            "{GOOD}{}",
            WITH_ROD.replace("rest_length = 0.5", &format!("rest_length = {bad}"))
        );
        let line = text
            .lines()
            .position(|l| l.starts_with("rest_length"))
            .unwrap()
            + 1;
        let e = Scene::parse("scenes/x.toml", &text)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!("scenes/x.toml:{line}: rod[0].rest_length: ")),
            "{e}"
        );
    }
}

#[test]
fn a_rod_between_coincident_centres_is_refused() {
    let text = format!("{GOOD}{WITH_ROD}")
        .replace("position = [0.0, 1.0, 0.0]", "position = [0.0, 0.0, 0.0]");
    let e = Scene::parse("scenes/x.toml", &text)
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(e.contains("rod[0].b") && e.contains("coincide"), "{e}");
}

/// A scene with one `[[tile]]` group, for the tile errors.
const TILED: &str = r#"
frames = 10
ci_frames = 5

[[body]]
name = "floor"
kind = "fixed"
shape = "plane"

[[tile]]
name = "stairs"
repeat = [3, 2]
spacing = [2.0, 4.0]
[[tile.body]]
name = "step"
kind = "fixed"
shape = "box"
half_extents = [0.5, 0.1, 0.2]
position = [1.0, 0.1, 0.0]
[[tile.body]]
name = "wall"
kind = "fixed"
shape = "box"
half_extents = [0.5, 0.3, 0.05]
position = [1.0, 0.3, 1.0]
"#;

fn tiled_error(from: &str, to: &str) -> String {
    assert!(TILED.contains(from), "test setup: {from:?} not in scene");
    let text = TILED.replacen(from, to, 1);
    Scene::parse("scenes/t.toml", &text)
        .and_then(|s| s.build().map(|_| ()))
        .expect_err("must fail")
        .to_string()
}

fn tiled_line(needle: &str) -> usize {
    TILED.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn a_tile_is_copied_over_its_grid() {
    let scene = Scene::parse("scenes/t.toml", TILED).unwrap();
    assert_eq!(scene.def.ci_frames, Some(5));
    let world = scene.build().unwrap().world;
    assert_eq!(world.bodies.len(), 1 + 2 * 3 * 2);
    let corner = world.body(world.find_body("stairs_2_1_wall").unwrap());
    assert_eq!(corner.position.to_array(), [5.0, 0.3, 5.0]);
    let first = world.body(world.find_body("stairs_0_0_step").unwrap());
    assert_eq!(first.position.to_array(), [1.0, 0.1, 0.0]);
}

#[test]
fn zero_copies_in_a_tile() {
    let e = tiled_error("repeat = [3, 2]", "repeat = [3, 0]");
    let line = tiled_line("repeat =");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].repeat: ")),
        "{e}"
    );
    assert!(e.contains("at least 1"), "{e}");
}

#[test]
fn negative_copies_in_a_tile_is_a_type_error() {
    let e = tiled_error("repeat = [3, 2]", "repeat = [-3, 2]");
    let line = tiled_line("repeat =");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].repeat")),
        "{e}"
    );
}

#[test]
fn non_positive_tile_spacing() {
    let e = tiled_error("spacing = [2.0, 4.0]", "spacing = [2.0, 0.0]");
    let line = tiled_line("spacing =");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].spacing: ")),
        "{e}"
    );
    assert!(e.contains("positive"), "{e}");
}

#[test]
fn a_tile_copies_fixed_bodies_only() {
    let e = tiled_error(
        "name = \"wall\"\nkind = \"fixed\"",
        "name = \"wall\"\nkind = \"dynamic\"",
    );
    let line = tiled_line("name = \"wall\"") + 1;
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].body[1].kind: ")),
        "{e}"
    );
    assert!(e.contains("fixed"), "{e}");
}

#[test]
fn a_bad_body_in_a_tile_names_its_field() {
    let e = tiled_error(
        "half_extents = [0.5, 0.3, 0.05]",
        "half_extents = [0.5, -0.3, 0.05]",
    );
    let line = tiled_line("half_extents = [0.5, 0.3, 0.05]");
    assert!(
        e.starts_with(&format!(
            "scenes/t.toml:{line}: tile[0].body[1].half_extents: "
        )),
        "{e}"
    );
}

#[test]
fn duplicate_body_names_in_a_tile() {
    let e = tiled_error("name = \"wall\"", "name = \"step\"");
    let line = tiled_line("name = \"wall\"");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].body[1].name: ")),
        "{e}"
    );
    assert!(e.contains("duplicate"), "{e}");
}

#[test]
fn tile_copies_clashing_with_a_body() {
    let e = tiled_error("name = \"floor\"", "name = \"stairs_0_0_step\"");
    let line = tiled_line("name = \"step\"");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: tile[0].body[0].name: ")),
        "{e}"
    );
}

#[test]
fn ci_frames_beyond_frames() {
    let e = tiled_error("ci_frames = 5", "ci_frames = 50");
    let line = tiled_line("ci_frames =");
    assert!(
        e.starts_with(&format!("scenes/t.toml:{line}: ci_frames: ")),
        "{e}"
    );
    assert!(e.contains("[1, frames = 10]"), "{e}");
}

#[test]
fn negative_joint_damping() {
    let e = error_for("iterations = 10", "iterations = 10\njoint_damping = -1.0");
    assert!(e.starts_with("scenes/x.toml:4: joint_damping: "), "{e}");
}

/// A `[[variant]]` is a second method for the same scene: its settings override the file's
/// (and the rest stay), it is named `<scene>_<variant>`, and its mistakes are reported at its
/// own lines like any other field's.
#[test]
fn variants_override_the_settings_and_their_mistakes_name_their_lines() {
    let variant = "\n[[variant]]\nname = \"fast\"\nsubsteps = 4\niterations = 2\n\
                   joint_damping = 0.5\nsleep = true\n";
    let scene = Scene::parse("scenes/x.toml", &format!("{GOOD}{variant}")).unwrap();
    let fast = scene.variant("fast").unwrap();
    assert_eq!(fast.name(), "x_fast");
    let (base, fast) = (scene.build().unwrap().world, fast.build().unwrap().world);
    assert_eq!((base.settings.substeps, base.settings.iterations), (1, 10));
    assert_eq!((fast.settings.substeps, fast.settings.iterations), (4, 2));
    assert_eq!(fast.settings.joint_damping, 0.5);
    assert!(fast.settings.sleep && !base.settings.sleep);
    assert_eq!(fast.settings.dt, base.settings.dt);
    let unknown = scene.variant("slow").unwrap_err().to_string();
    assert!(
        unknown.contains("no [[variant]] named \"slow\" (the file has fast)"),
        "{unknown}"
    );

    let line = GOOD.lines().count() + 3; // the blank line, [[variant]], name
    let error = |text: &str| {
        Scene::parse("scenes/x.toml", &format!("{GOOD}{text}"))
            .expect_err("must fail")
            .to_string()
    };
    let e = error("\n[[variant]]\nname = \"Fast One\"\n");
    assert!(
        e.starts_with(&format!("scenes/x.toml:{line}: variant[0].name: ")),
        "{e}"
    );
    let e = error("\n[[variant]]\nname = \"fast\"\niterations = 0\n");
    assert_eq!(
        e,
        format!(
            "scenes/x.toml:{}: variant[0].iterations: must be a whole number from 1 to 10000, got 0",
            line + 1
        )
    );
    let e = error("\n[[variant]]\nname = \"fast\"\nframes = 10\n");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: variant[0].frames: unknown field",
            line + 1
        )),
        "{e}"
    );
    let e = error("\n[[variant]]\niterations = 4\n");
    assert_eq!(
        e,
        format!(
            "scenes/x.toml:{}: variant[0]: a [[variant]] needs a name or a method (it names a recording)",
            line - 1
        )
    );
    let e = error("\n[[variant]]\nname = \"fast\"\nalpha_b = 0.3\n");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: variant[0].alpha_b: unknown field",
            line + 1
        )),
        "{e}"
    );
    let e = error("\n[[variant]]\nname = \"a\"\n[[variant]]\nname = \"a\"\n");
    assert!(
        e.contains("variant[1].name: a variant named \"a\" comes earlier"),
        "{e}"
    );
}

/// A rod's stiffness in physical units: positive, not beside the alpha it replaces, damping
/// only with a stiffness; the ragdoll's rod spine checks the same fields.
#[test]
fn rod_stiffness_mistakes_name_the_field() {
    let rod_error = |from: &str, to: &str| {
        let text = format!("{GOOD}{WITH_ROD}").replacen(from, to, 1);
        let e = Scene::parse("scenes/x.toml", &text)
            .unwrap_err()
            .to_string();
        let line = move |field: &str| text.lines().position(|l| l.starts_with(field)).unwrap() + 1;
        (e, line)
    };
    let (e, line) = rod_error("alpha_b = 0.1", "bend_stiffness = -5.0");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: rod[0].bend_stiffness: ",
            line("bend_stiffness")
        )),
        "{e}"
    );
    assert!(e.contains("positive"), "{e}");
    let (e, line) = rod_error("alpha_b = 0.1", "alpha_b = 0.1\nbend_stiffness = 50.0");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: rod[0].bend_stiffness: ",
            line("bend_stiffness")
        )),
        "{e}"
    );
    assert!(e.contains("replaces alpha_b"), "{e}");
    let (e, line) = rod_error("alpha_b = 0.1", "twist_damping = 1.0");
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: rod[0].twist_damping: ",
            line("twist_damping")
        )),
        "{e}"
    );
    let e = error_for(
        r#"spine = "chain3""#,
        "spine = \"rod\"\nalpha_t = 0.5\ntwist_stiffness = 10.0",
    );
    assert!(
        e.starts_with(&format!(
            "scenes/x.toml:{}: ragdoll[0].twist_stiffness: ",
            line_of("spine =") + 2
        )),
        "{e}"
    );
    // a good stiff rod reaches the solver's rod
    let text = format!("{GOOD}{WITH_ROD}")
        .replace("alpha_b = 0.1", "bend_stiffness = 50.0\nbend_damping = 2.0");
    let world = Scene::parse("scenes/x.toml", &text)
        .unwrap()
        .build()
        .unwrap()
        .world;
    let rod = world
        .constraints
        .iter()
        .find_map(|c| match c {
            rodlab::constraint::Constraint::Rod(r) => Some(r),
            _ => None,
        })
        .unwrap();
    assert_eq!(
        rod.params.bend_stiffness,
        Some(rodlab::constraint::Stiffness {
            stiffness: 50.0,
            damping: 2.0
        })
    );
    assert_eq!(
        (rod.params.alpha_bend, rod.params.twist_stiffness),
        (0.0, None)
    );
}

/// The command line's rod overrides: a stiffness replaces the file's alpha (and an alpha the
/// file's stiffness); a rod flag on a scene without rods, or damping with no stiffness to damp,
/// is an error naming the flag, never dropped.
#[test]
fn rod_overrides_replace_each_other_and_refuse_what_they_cannot_do() {
    use rodlab::scene::{RodOverrides, SoftnessOverride};
    use rodlab::sim::Overrides;
    let bend = |bend: SoftnessOverride| Overrides {
        rod: RodOverrides {
            bend,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut scene = Scene::parse("scenes/x.toml", GOOD).unwrap();
    let damping_only = bend(SoftnessOverride {
        damping: Some(1.0),
        ..Default::default()
    });
    damping_only.apply(&mut scene.def);
    let e = damping_only.check_applied(&scene.def).unwrap_err();
    assert!(e.starts_with("--bend-damping: the scene has no rod"), "{e}");
    let stiff = Overrides {
        spine: Some(rodlab::ragdoll::SpineKind::Rod),
        ..bend(SoftnessOverride {
            stiffness: Some(80.0),
            ..Default::default()
        })
    };
    let mut scene = Scene::parse("scenes/x.toml", GOOD).unwrap();
    scene.def.ragdoll[0].alpha_b = Some(0.2);
    stiff.apply(&mut scene.def);
    stiff.check_applied(&scene.def).unwrap();
    let r = &scene.def.ragdoll[0];
    assert_eq!((r.alpha_b, r.bend_stiffness), (None, Some(80.0)));
    let e = damping_only.check_applied(&{
        let mut def = scene.def.clone();
        def.ragdoll[0].bend_stiffness = None;
        def
    });
    assert!(e.unwrap_err().starts_with("--bend-damping damps"));
    let alpha = bend(SoftnessOverride {
        alpha: Some(0.3),
        ..Default::default()
    });
    alpha.apply(&mut scene.def);
    let r = &scene.def.ragdoll[0];
    assert_eq!((r.alpha_b, r.bend_stiffness), (Some(0.3), None));
}

/// The documented bounds (`src/scene/bounds.rs`): counts that would never finish or would not
/// fit in memory, numbers that are not finite, names that would write outside the output
/// folder, starting speeds past the explosion bounds: each refused, naming its line and field.
#[test]
fn numbers_out_of_their_bounds_name_their_field() {
    let cases = [
        (
            "iterations = 10",
            "iterations = 2147483647",
            "iterations",
            "from 1 to 10000",
        ),
        ("dt = 0.01", "dt = 5.0", "dt", "at most 1 (s)"),
        (
            "dt = 0.01",
            "dt = 0.01\ncontact_extra_sweeps = 100000",
            "contact_extra_sweeps",
            "from 0 to 10000",
        ),
        (
            "dt = 0.01",
            "dt = 0.01\ncontact_margin = nan",
            "contact_margin",
            "distance",
        ),
        (
            "dt = 0.01",
            "dt = 0.01\ngravity = [0.0, -1e30, 0.0]",
            "gravity",
            "finite",
        ),
        (
            "dt = 0.01",
            "dt = 0.01\nname = \"../../x\"",
            "name",
            "cannot name a recording",
        ),
        (
            "half_extents = [1.0, 0.1, 1.0]",
            "half_extents = [1e30, 0.1, 1.0]",
            "body[0].half_extents",
            "finite",
        ),
        (
            "position = [0.0, 1.0, 0.0]",
            "position = [0.0, nan, 0.0]",
            "body[1].position",
            "finite",
        ),
        (
            "position = [0.0, 1.0, 0.0]",
            "position = [0.0, 1.0, 0.0]\nvelocity = [1000.0, 0.0, 0.0]",
            "body[1].velocity",
            "max_speed",
        ),
        (
            "anchor = [0.0, 0.5, 0.0]",
            "anchor = [0.0, inf, 0.0]",
            "joint[0].anchor",
            "finite",
        ),
        (
            "spine = \"chain3\"",
            "spine = \"chain3\"\nalpha_b = 2.0",
            "ragdoll[0].alpha_b",
            "[0, 1]",
        ),
        (
            "spine = \"chain3\"",
            "spine = \"chain3\"\nposition = [inf, 0.0, 0.0]",
            "ragdoll[0].position",
            "finite",
        ),
    ];
    for (from, to, field, words) in cases {
        let e = error_for(from, to);
        let text = GOOD.replacen(from, to, 1);
        let needle = to.lines().last().unwrap();
        let line = text.lines().position(|l| l == needle).unwrap() + 1;
        assert!(
            e.starts_with(&format!("scenes/x.toml:{line}: {field}: ")),
            "{to}: {e}"
        );
        assert!(e.contains(words), "{to}: {e}");
    }
    // a [drop] block too large to allocate is refused before it makes its ragdolls
    let text = format!(
        "{GOOD}\n[drop]\ncount = 18446744073709551615\nfirst = [0.0, 1.0, 0.0]\nspacing = [1.0, 2.0, 1.0]\ncolumns = 2\nrows = 2\n"
    );
    let e = Scene::parse("scenes/x.toml", &text)
        .unwrap_err()
        .to_string();
    let line = text.lines().position(|l| l.starts_with("count")).unwrap() + 1;
    assert!(
        e.starts_with(&format!("scenes/x.toml:{line}: drop.count: ")),
        "{e}"
    );
}

#[test]
fn a_file_that_is_not_utf8_names_the_line_of_its_bad_byte() {
    let path = std::env::temp_dir().join(format!("rodlab-not-utf8-{}.toml", std::process::id()));
    let mut bytes = GOOD.as_bytes().to_vec();
    let at = GOOD.find("frames").unwrap();
    bytes.insert(at, 0xFF);
    std::fs::write(&path, bytes).unwrap();
    let e = Scene::load(&path).unwrap_err().to_string();
    let line = line_of("frames =");
    assert!(
        e.starts_with(&format!("{}:{line}: not UTF-8", path.display())),
        "{e}"
    );
}

#[test]
fn record_every_zero_names_its_field() {
    let text = format!("{GOOD}\n[record]\nevery = 0\n");
    let e = Scene::parse("scenes/x.toml", &text)
        .unwrap_err()
        .to_string();
    let line = text.lines().position(|l| l.starts_with("every")).unwrap() + 1;
    assert!(
        e.starts_with(&format!("scenes/x.toml:{line}: record.every: ")),
        "{e}"
    );
}

/// `--seed` lays a `[drop]` block's ragdolls out again, as the file would with that seed: new
/// yaws and tips at the same grid places, what a variant set on them kept, the file's own
/// ragdolls untouched; on a scene without a `[drop]` block it is an error naming the flag.
#[test]
fn seed_lays_out_the_drop_again_and_needs_a_drop_block() {
    use rodlab::sim::Overrides;
    let parse =
        |seed| Scene::parse("scenes/x.toml", &crate::common::small_drop_scene(3, seed)).unwrap();
    let mut reseeded = parse(7).variant("no_self_contacts").unwrap();
    let seeded = Overrides {
        seed: Some(99),
        ..Default::default()
    };
    seeded.apply(&mut reseeded.def);
    seeded.check_applied(&reseeded.def).unwrap();
    let (file7, file99) = (parse(7), parse(99));
    let poses = |def: &rodlab::scene::SceneDef| -> Vec<([f32; 3], [f32; 3])> {
        def.ragdoll
            .iter()
            .map(|r| (r.position, r.rotation))
            .collect()
    };
    assert_eq!(poses(&reseeded.def), poses(&file99.def));
    assert_ne!(
        poses(&reseeded.def),
        poses(&file7.def),
        "the seed moved nothing"
    );
    let names: Vec<&str> = reseeded
        .def
        .ragdoll
        .iter()
        .map(|r| r.name.as_str())
        .collect();
    assert_eq!(names, ["alone", "drop00", "drop01", "drop02"]);
    assert_eq!(reseeded.def.ragdoll[0].position, [0.0, 0.0, 3.0]);
    assert!((reseeded.def.ragdoll.iter())
        .all(|r| r.self_contacts == rodlab::ragdoll::SelfContacts::None));
    let mut no_drop = Scene::parse("scenes/x.toml", GOOD).unwrap();
    seeded.apply(&mut no_drop.def);
    let e = seeded.check_applied(&no_drop.def).unwrap_err();
    assert!(e.starts_with("--seed lays out a [drop] block"), "{e}");
}
