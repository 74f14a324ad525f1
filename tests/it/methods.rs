//! Named methods (`method = "paper" | "game" | "tight"`): which setting wins where, and what
//! the game method buys on a user's own boxes against the paper's method.

use rodlab::scene::{Method, Overrides, Scene};

/// A scene of boxes on a floor at `method`, with `extra` top-level keys and the boxes' centres.
fn boxes_scene(method: &str, extra: &str, centres: &[[f32; 3]]) -> Scene {
    let mut text = format!(
        "method = \"{method}\"\nframes = 600\ncontacts = true\n{extra}\n\
         [[body]]\nname = \"floor\"\nkind = \"fixed\"\nshape = \"plane\"\n"
    );
    for (i, c) in centres.iter().enumerate() {
        text += &format!(
            "[[body]]\nname = \"box{i}\"\nshape = \"box\"\nhalf_extents = [0.25, 0.25, 0.25]\n\
             mass = 1.0\nposition = [{}, {}, {}]\n",
            c[0], c[1], c[2]
        );
    }
    Scene::parse("boxes.toml", &text).unwrap()
}

/// A scene's own keys win over its method's; a variant's over its method's; the command line's
/// flags over `--method`, which replaces the scene's method whole.
#[test]
fn single_fields_win_over_their_method() {
    let scene = boxes_scene("game", "iterations = 8\n[[variant]]\nmethod = \"tight\"\n[[variant]]\nname = \"coarse\"\nmethod = \"game\"\nsubsteps = 2\n", &[[0.0, 0.25, 0.0]]);
    let d = &scene.def;
    assert_eq!((d.substeps, d.iterations), (4, 8), "the file's iterations");
    assert!(d.sleep && d.joint_friction == 1.0 && d.contact_hertz == 90.0);
    let names: Vec<&str> = scene.variant_names().collect();
    assert_eq!(
        names,
        ["tight", "coarse"],
        "a variant of a method alone is named after it"
    );
    let tight = scene.variant("tight").unwrap().def;
    assert_eq!(
        (tight.substeps, tight.iterations, tight.contact_extra_sweeps),
        (20, 1, 6)
    );
    assert!(!tight.sleep);
    let coarse = scene.variant("coarse").unwrap().def;
    assert_eq!(
        (coarse.substeps, coarse.iterations),
        (2, 4),
        "the variant's substeps"
    );
    let mut paper = scene.clone();
    Overrides {
        method: Some(Method::Paper),
        iterations: Some(5),
        ..Default::default()
    }
    .apply(&mut paper.def);
    let p = &paper.def;
    assert_eq!(
        (p.substeps, p.iterations, p.method),
        (1, 5, Some(Method::Paper))
    );
    assert!(!p.sleep && p.joint_friction == 0.0 && p.contact_hertz == 0.0);
}

/// A method that does not exist is refused at its line, with the choices.
#[test]
fn an_unknown_method_names_its_line_and_the_choices() {
    let e = Scene::parse("x.toml", "frames = 10\nmethod = \"fast\"\n").unwrap_err();
    let message = e.to_string();
    assert!(message.starts_with("x.toml:2: method:"), "{message}");
    assert!(
        message.contains("paper") && message.contains("tight"),
        "{message}"
    );
}

/// Runs a boxes scene for its frames: the farthest any box ended from its start (m), and the
/// fastest any box moved at any frame (m/s).
fn drift_and_top_speed(scene: &Scene, centres: &[[f32; 3]]) -> (f32, f32) {
    let mut lab = scene.build().unwrap();
    let mut fastest = 0.0f32;
    for _ in 0..scene.def.frames {
        lab.step().unwrap();
        let speeds = lab.world.bodies.iter().map(|b| b.linear_velocity.length());
        fastest = speeds.fold(fastest, f32::max);
    }
    let drift = (centres.iter().enumerate())
        .map(|(i, c)| {
            let id = lab.world.find_body(&format!("box{i}")).unwrap();
            (lab.world.body(id).position - glam::Vec3::from(*c)).length()
        })
        .fold(0.0f32, f32::max);
    (drift, fastest)
}

fn stack(n: usize) -> Vec<[f32; 3]> {
    (0..n).map(|i| [0.0, 0.25 + 0.5 * i as f32, 0.0]).collect()
}

fn pyramid(base: usize) -> Vec<[f32; 3]> {
    let mut centres = Vec::new();
    for row in 0..base {
        for k in 0..base - row {
            let x = (k as f32 - (base - 1 - row) as f32 * 0.5) * 0.5;
            centres.push([x, 0.25 + 0.5 * row as f32, 0.0]);
        }
    }
    centres
}

/// Boxes started half sunk into the box below (pairs) and a block of nine started inside each
/// other.
fn deep_overlaps() -> Vec<[f32; 3]> {
    let sunk = (0..4).flat_map(|i| [[0.0, 0.25, 2.0 * i as f32], [0.1, 0.5, 2.0 * i as f32]]);
    let block = (0..9).map(|k| {
        let (i, j) = ((k / 3) as f32, (k % 3) as f32);
        [4.0 + 0.25 * i, 0.25 + 0.05 * j, 0.25 * j]
    });
    sunk.chain(block).collect()
}

/// Where each method holds and fails on a user's boxes, 10 s each (the farthest a box ends
/// from its start; the fastest a box moves):
/// - a ten-wide pyramid (55 boxes): the paper's method creeps by 19 cm; game holds it within
///   5 mm (1.2 mm, asleep) and tight within 2 cm (1.9 cm);
/// - a ten-box stack: the paper's leans 10 cm; game stands within 5 mm (3.2 mm, nearly all of
///   it the soft contacts' sag) and sleeps; tight within 2 mm;
/// - boxes started deep inside each other: the paper's method throws them apart at over 5 m/s
///   (8.2 m/s); game pushes them out at no more than its 3 m/s cap (2.8 m/s) and tight at no
///   more than its 5 m/s (4.4 m/s; tight without the cap threw them at 90-200 m/s).
#[test]
fn the_game_method_holds_stacks_and_separates_overlap_gently() {
    let run = |method: &str, centres: &[[f32; 3]]| {
        drift_and_top_speed(&boxes_scene(method, "", centres), centres)
    };
    let (pyramid, stack) = (pyramid(10), stack(10));
    let [paper, game, tight] = ["paper", "game", "tight"].map(|m| run(m, &pyramid).0);
    println!("pyramid, farthest from the start: paper {paper:.4} m, game {game:.4} m, tight {tight:.4} m");
    assert!(
        paper > 0.05 && game < 5e-3 && tight < 0.02,
        "pyramid: paper {paper} m, game {game} m, tight {tight} m"
    );
    let [paper, game, tight] = ["paper", "game", "tight"].map(|m| run(m, &stack).0);
    println!(
        "stack, farthest from the start: paper {paper:.4} m, game {game:.4} m, tight {tight:.4} m"
    );
    assert!(
        paper > 0.05 && game < 5e-3 && tight < 2e-3,
        "stack: paper {paper} m, game {game} m, tight {tight} m"
    );
    let overlaps = deep_overlaps();
    let [paper, game, tight] = ["paper", "game", "tight"].map(|m| run(m, &overlaps).1);
    println!(
        "overlap, fastest box: paper {paper:.2} m/s, game {game:.2} m/s, tight {tight:.2} m/s"
    );
    assert!(
        paper > 5.0 && game <= 3.0 && tight <= 5.0,
        "overlap: paper {paper} m/s, game {game} m/s, tight {tight} m/s"
    );
}

/// Each method setting is declared once, and a scene file's key, a `[[variant]]`'s key and the
/// sweep's and `run`'s flags all take it from there: every declared setting at its `tight`
/// value reads back from both keys into the world's settings, and a value out of its bounds is
/// refused at its line, naming the field, from both.
#[test]
fn every_declared_setting_is_a_scene_key_and_a_variant_key_with_its_bounds() {
    use rodlab::solver::{Bounds, METHOD_SETTINGS};
    use rodlab::world::Settings;
    let mut tight = Settings::default();
    let mut def: rodlab::scene::SceneDef = toml::from_str("").unwrap();
    Method::Tight.overrides().apply(&mut def);
    def.write_method_settings(&mut tight);
    // a choice is a TOML string; numbers (inf too) and switches are bare
    let quoted = |text: String| match text.parse::<f64>().is_ok() || text.parse::<bool>().is_ok() {
        true => text,
        false => format!("\"{text}\""),
    };
    for ((name, text), declared) in tight.method_texts().into_iter().zip(METHOD_SETTINGS) {
        assert_eq!(name, declared.name);
        let key = format!("{name} = {}", quoted(text.clone()));
        let scene = Scene::parse(
            "s.toml",
            &format!("{key}\n[[variant]]\nname = \"v\"\n{key}\n"),
        )
        .unwrap_or_else(|e| panic!("{key}: {e}"));
        let value_in = |def: &rodlab::scene::SceneDef| {
            let mut read = Settings::default();
            def.write_method_settings(&mut read);
            let texts = read.method_texts();
            texts.into_iter().find(|(n, _)| *n == name).unwrap().1
        };
        assert_eq!(value_in(&scene.def), text);
        assert_eq!(value_in(&scene.variant("v").unwrap().def), text);
        // below its bounds: refused at the line, naming the field
        let below = match declared.bounds {
            Bounds::Count { min: 0, .. } | Bounds::Any => continue,
            Bounds::Count { .. } => "0".to_string(),
            Bounds::Number { .. } => "-1.0".to_string(),
        };
        for (text, line, field) in [
            (
                format!("frames = 3\n{name} = {below}\n"),
                2,
                name.to_string(),
            ),
            (
                format!("[[variant]]\nname = \"v\"\n{name} = {below}\n"),
                3,
                format!("variant[0].{name}"),
            ),
        ] {
            let e = Scene::parse("s.toml", &text).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("s.toml:{line}: {field}: must be")),
                "{text}: {e}"
            );
        }
    }
}

/// docs/scene-format.md holds `rodlab settings`' table as the declarations print it.
#[test]
fn the_scene_format_docs_hold_the_declared_settings_table() {
    let docs =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scene-format.md"))
            .unwrap();
    let table = docs
        .split("<!-- rodlab settings -->\n")
        .nth(1)
        .and_then(|rest| rest.split("<!-- end rodlab settings -->").next())
        .expect("the markers around the table");
    assert_eq!(
        table.trim(),
        rodlab::scene::settings_table().trim(),
        "regenerate the table with `rodlab settings`"
    );
}
