//! Scenes that pass or fail `check` for the right reason, and quickly: the `[[tile]]` groups'
//! bodies bounded all together, a rod's normal finite, a bad setting blamed on itself; and a
//! valid scene whose run explodes (the rain at dt = 1 s) stopped with the usual error before
//! its memory runs away.

use std::time::{Duration, Instant};

use rodlab::scene::bounds::MAX_TILE_BODIES;
use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver, Overrides};

use crate::common::{decode, frames_with, temp_path};

/// `groups` `[[tile]]` groups of one box, `per_group` copies each.
fn tiled_boxes(groups: usize, per_group: u64) -> String {
    let mut text = String::from("dt = 0.01\nframes = 10\n");
    for g in 0..groups {
        text += &format!(
            "\n[[tile]]\nname = \"g{g}\"\nrepeat = [{per_group}, 1]\nspacing = [1.0, 1.0]\n\
             [[tile.body]]\nname = \"b\"\nkind = \"fixed\"\nshape = \"box\"\n\
             half_extents = [0.1, 0.1, 0.1]\n"
        );
    }
    text
}

/// Three groups within the bound each but past it together are refused, at the group that
/// passes it, at once; groups at the bound together check (and build) within seconds.
#[test]
fn tile_groups_are_bounded_all_together_and_check_quickly() {
    let started = Instant::now();
    let text = tiled_boxes(3, MAX_TILE_BODIES);
    let error = Scene::parse("scenes/t.toml", &text)
        .unwrap_err()
        .to_string();
    let repeats = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("repeat"));
    let line = repeats.map(|(i, _)| i + 1).nth(1).unwrap();
    assert!(
        error.starts_with(&format!("scenes/t.toml:{line}: tile[1].repeat: ")),
        "{error}"
    );
    assert!(error.contains("together"), "{error}");
    let at_bound = Scene::parse("scenes/t.toml", &tiled_boxes(3, MAX_TILE_BODIES / 3)).unwrap();
    let lab = at_bound.build().unwrap();
    assert_eq!(lab.world.bodies.len() as u64, MAX_TILE_BODIES / 3 * 3);
    let elapsed = started.elapsed();
    assert!(elapsed < Duration::from_secs(20), "{elapsed:?}");
}

const TWO_SPHERES_AND_A_ROD: &str = r#"
dt = 0.01
frames = 10

[[body]]
name = "a"
shape = "sphere"
radius = 0.1
mass = 1.0

[[body]]
name = "b"
shape = "sphere"
radius = 0.1
mass = 1.0
position = [0.0, 1.0, 0.0]

[[rod]]
name = "r"
a = "a"
b = "b"
normal = [0.0, 0.0, 1.0]
"#;

/// A rod's normal with NaN or an infinity has no direction: refused at its line.
#[test]
fn a_rods_normal_must_be_finite() {
    let line = TWO_SPHERES_AND_A_ROD
        .lines()
        .position(|l| l.starts_with("normal"))
        .unwrap()
        + 1;
    for bad in ["nan", "inf", "-inf"] {
        let text = TWO_SPHERES_AND_A_ROD.replace("[0.0, 0.0, 1.0]", &format!("[{bad}, 0.0, 1.0]"));
        let error = Scene::parse("scenes/r.toml", &text)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with(&format!(
                "scenes/r.toml:{line}: rod[0].normal: must be finite"
            )),
            "{bad}: {error}"
        );
    }
    assert!(Scene::parse("scenes/r.toml", TWO_SPHERES_AND_A_ROD).is_ok());
}

/// `max_speed = -1` in the rain is blamed on `max_speed` at its own line, not on the first
/// body whose velocity it bounds (a tile body's, at another line).
#[test]
fn a_bad_setting_is_blamed_on_itself() {
    let rain = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/ragdoll_rain.toml"
    ))
    .unwrap();
    let text = rain.replacen("iterations = 2\n", "iterations = 2\nmax_speed = -1\n", 1);
    let line = text.lines().position(|l| l == "max_speed = -1").unwrap() + 1;
    let error = Scene::parse("scenes/rain.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with(&format!("scenes/rain.toml:{line}: max_speed: ")),
        "{error}"
    );
}

/// The rain at dt = 1 s passes `check` (every value is within its bound), and its bodies
/// sweep metres through each other in a step: the run stops with the usual error (frame,
/// body, constraint) within two frames instead of growing gigabytes of contact pairs.
#[test]
fn the_rain_at_a_one_second_step_stops_with_the_usual_error() {
    let mut scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/ragdoll_rain.toml"
    ))
    .unwrap();
    Overrides {
        dt: Some(1.0),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let mut lab = scene.build().unwrap();
    let error = sim::run(&mut lab, 10, &mut NoObserver).unwrap_err();
    let error = error
        .downcast_ref::<rodlab::world::SimulationError>()
        .expect("a simulation error");
    assert!(error.frame <= 2, "{error}");
    assert!(error.constraint.is_some(), "{error}");
    assert!(error.reason.starts_with("exploded"), "{error}");
}

/// The same run from the command line, its memory bounded at 2 GB: the usual error and exit
/// code 1 (not an abort), and the recording up to the failing frame stays readable.
#[test]
fn the_rain_at_a_one_second_step_records_up_to_its_failure() {
    let path = temp_path("rain_dt1.rrd");
    let script = format!(
        "ulimit -v 2000000; exec '{}' run '{}/scenes/ragdoll_rain.toml' --dt 1 --save '{}'",
        env!("CARGO_BIN_EXE_rodlab"),
        env!("CARGO_MANIFEST_DIR"),
        path.display()
    );
    let output = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("simulation stopped") && stderr.contains("exploded"),
        "{stderr}"
    );
    let frames = frames_with(&decode(&path), "world/ragdolls/capsules", "translations");
    assert!(frames.contains(&0) && frames.len() <= 2, "{frames:?}");
}

/// Loose bodies (no groups: the grid's rebuild) crowded into one spot make a pair each with
/// every other; past the broad phase's budget the step stops with the usual error, at frame 1,
/// naming a body.
#[test]
fn a_crowd_past_the_pair_budget_stops_at_its_first_step() {
    use rodlab::body::{Body, BodyKind};
    use rodlab::math::{Quat, Vec3};
    use rodlab::shape::Shape;
    use rodlab::world::{Settings, World};
    let mut world = World::new(Settings {
        contacts: true,
        ..Settings::default()
    });
    // 2000 spheres within 2 cm: 2 million pairs, past the budget of 2^20 + 64 a body
    for i in 0..2000 {
        let at = Vec3::new(0.01 * (i % 2) as f32, 1.0 + 0.01 * (i % 3) as f32, 0.0);
        let ball = Body::new(
            format!("ball{i}"),
            BodyKind::Dynamic,
            Shape::Sphere { radius: 0.1 },
            1.0,
        );
        world.add_body(ball.with_pose(at, Quat::IDENTITY));
    }
    let error = world.step().unwrap_err();
    assert_eq!(error.frame, 1, "{error}");
    assert!(error.body.starts_with("ball"), "{error}");
    assert!(error.reason.contains("candidate pairs"), "{error}");
}
