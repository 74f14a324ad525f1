//! Helpers shared by the tests: scenes built with overrides, and reading recordings back.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};

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

/// Frames at which `entity` received a component whose name ends with `component`.
pub fn frames_with(chunks: &[Chunk], entity: &str, component: &str) -> BTreeSet<i64> {
    let mut frames = BTreeSet::new();
    for chunk in chunks
        .iter()
        .filter(|c| c.entity_path().to_string() == format!("/{entity}") && !c.is_static())
    {
        if !chunk
            .component_descriptors()
            .any(|d| d.component.as_str().ends_with(component))
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
                .find(|d| d.component.as_str().ends_with(component))
                .expect("the static chunk has the component");
            c.iter_slices::<String>(d.component)
                .flatten()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
        })
        .collect()
}
