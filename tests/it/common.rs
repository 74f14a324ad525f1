//! Helpers shared by the tests: scenes built with overrides, and reading recordings back.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};

/// Calls `$f::<L>(args)` with `L` the `$w`-lane type: this CPU's where it runs it, else the
/// portable type of that width, which computes the same bits (`rodlab::lanes::portable`).
macro_rules! at_width {
    ($w:expr, $($f:ident)::+ ($($arg:expr),* $(,)?)) => {{
        use rodlab::lanes::{portable::Portable, F32x16, F32x4, F32x8, LaneWidth};
        match $w {
            4 => $($f)::+::<F32x4>($($arg),*),
            8 if LaneWidth::W8.is_available() => $($f)::+::<F32x8>($($arg),*),
            8 => $($f)::+::<Portable<8>>($($arg),*),
            16 if LaneWidth::W16.is_available() => $($f)::+::<F32x16>($($arg),*),
            16 => $($f)::+::<Portable<16>>($($arg),*),
            w => panic!("no {w}-lane type"),
        }
    }};
}

/// The lab of `scenes/<name>.toml` with `overrides` applied, and the frames the scene then asks
/// for.
pub fn lab_with(name: &str, overrides: rodlab::sim::Overrides) -> (rodlab::lab::Lab, u32) {
    let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut scene = rodlab::scene::Scene::load(path).unwrap();
    overrides.apply(&mut scene.def);
    (scene.build().unwrap(), scene.def.frames)
}

/// A path in this test process's own temporary folder.
pub fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rodlab-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// All data chunks of the recording (not the blueprint), decoded with Rerun's decoder.
pub fn decode(path: &Path) -> Vec<Chunk> {
    decode_messages(path, true)
}

/// The data chunks of a file cut short (a killed run's): every message up to the first one
/// that does not decode.
pub fn decode_prefix(path: &Path) -> Vec<Chunk> {
    decode_messages(path, false)
}

fn decode_messages(path: &Path, strict: bool) -> Vec<Chunk> {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut chunks = Vec::new();
    for msg in DecoderApp::decode_lazy(file) {
        let msg = match msg {
            Ok(msg) => msg,
            Err(e) if strict => panic!("recording does not decode: {e}"),
            Err(_) => break,
        };
        if let LogMsg::ArrowMsg(store, arrow) = msg {
            if store.kind() == rerun::StoreKind::Recording {
                chunks.push(Chunk::from_arrow_msg(&arrow).expect("chunk decodes"));
            }
        }
    }
    chunks
}

/// Asserts a run's final state hash ([`rodlab::world::World::state_hash`]) is the committed
/// one: a run of a chaotic scene (a pile: any change of rounding gives another) is pinned
/// exactly, as Box2D's determinism test pins its falling ragdolls. When the physics changes on
/// purpose, the failure names the new hash to commit (with `RODLAB_PRINT_HASHES` set, every
/// hash is printed and none asserted, to collect them in one run).
pub fn assert_state_hash(what: &str, hash: u64, committed: u64) {
    if std::env::var_os("RODLAB_PRINT_HASHES").is_some() {
        println!("state hash {what}: {hash:#018x}");
        return;
    }
    assert!(
        hash == committed,
        "{what}: final state hash {hash:#018x}, committed {committed:#018x}; if the physics \
         changed on purpose, commit the new hash"
    );
}

/// Whether a component's full name (`"Points3D:labels"`) is `component` (`"labels"`, which
/// `"Points3D:show_labels"` is not); any component for `""`.
fn is_component(name: &str, component: &str) -> bool {
    component.is_empty() || name.rsplit(':').next() == Some(component)
}

/// Frames at which `entity` received the component `component` (its name after the
/// archetype's).
pub fn frames_with(chunks: &[Chunk], entity: &str, component: &str) -> BTreeSet<i64> {
    let mut frames = BTreeSet::new();
    for chunk in chunks
        .iter()
        .filter(|c| c.entity_path().to_string() == format!("/{entity}") && !c.is_static())
    {
        if !chunk
            .component_descriptors()
            .any(|d| is_component(d.component.as_str(), component))
        {
            continue;
        }
        if let Some(column) = chunk.timelines().get(&"frame".into()) {
            frames.extend(column.times_raw().iter().copied());
        }
    }
    frames
}

/// The texts of the static component (its name ending with `component`, e.g. "labels" or
/// "text") of `entity`.
pub fn static_texts(chunks: &[Chunk], entity: &str, component: &str) -> Vec<String> {
    (chunks.iter())
        .filter(|c| c.is_static() && c.entity_path().to_string() == format!("/{entity}"))
        .flat_map(|c| {
            let d = (c.component_descriptors())
                .find(|d| is_component(d.component.as_str(), component))
                .expect("the static chunk has the component");
            c.iter_slices::<String>(d.component)
                .flatten()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
        })
        .collect()
}

/// A chain3 ragdoll ("r") standing on a floor (body 0) with contacts on, at rest or with its
/// left leg crossed over the right, filtering its own pairs as `self_contacts` says.
pub fn ragdoll_on_a_floor(
    self_contacts: rodlab::ragdoll::SelfContacts,
    crossed: bool,
) -> rodlab::world::World {
    use rodlab::body::{Body, BodyKind};
    use rodlab::math::{Quat, Vec3};
    use rodlab::ragdoll::{build_humanoid, HumanoidSpec, SpineKind};
    use rodlab::shape::Shape;
    use rodlab::world::{Settings, World};
    let mut world = World::new(Settings {
        contacts: true,
        ..Settings::default()
    });
    world.add_body(
        Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0)
            .with_pose(Vec3::ZERO, Quat::IDENTITY),
    );
    let mut spec = HumanoidSpec::new("r", SpineKind::Chain3);
    if crossed {
        spec.joint_rotations = vec![("hip_l".into(), Quat::from_rotation_z(-0.3))];
    }
    spec.self_contacts = self_contacts;
    build_humanoid(&mut world, &spec).unwrap();
    world
}

/// A small scene: a `[drop]` block of `count` chain3 ragdolls laid out with `seed`, one
/// `[[ragdoll]]` of its own ("alone"), and a variant filtering every ragdoll's own pairs
/// ("no_self_contacts").
pub fn small_drop_scene(count: u32, seed: u64) -> String {
    format!(
        r#"
dt = 0.016666668
iterations = 4
frames = 10
contacts = true
[drop]
count = {count}
spine = "chain3"
first = [0.0, 1.0, 0.0]
spacing = [1.0, 2.0, 1.0]
columns = 2
rows = 1
seed = {seed}
[[ragdoll]]
name = "alone"
position = [0.0, 0.0, 3.0]
[[variant]]
name = "no_self_contacts"
self_contacts = "none"
"#
    )
}
