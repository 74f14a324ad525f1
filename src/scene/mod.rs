//! Scene files: what users write (TOML, read with serde, unknown fields refused), checked,
//! then built into a [`Lab`](crate::lab::Lab) (a [`World`](crate::world::World) and its
//! ragdolls). The definitions here are separate from solver state.
//!
//! Every error reads `FILE:LINE: FIELD: message`, for syntax, type and semantic mistakes alike.
//!
//! | file | what |
//! |---|---|
//! | `def.rs` | the serde definitions and their defaults (method defaults read from `Settings::default`) |
//! | `expand.rs` | `[drop]` and `[[tile]]` expanded into ragdolls and bodies |
//! | `check.rs`, `check_items.rs` | semantic checks: the scene, then one item at a time |
//! | `bounds.rs` | documented numeric bounds (finite, sizes, counts) |
//! | `build.rs` | a checked scene built into a lab |
//! | `locate.rs` | field paths to file lines |
//! | `overrides.rs`, `variant.rs` | command-line overrides and `[[variant]]`s |

pub mod bounds;
mod build;
mod character;
mod check;
mod check_items;
mod def;
mod expand;
mod locate;
mod method;
mod overrides;
mod variant;

pub use build::LOOSE_GROUP;
pub use character::HANDOVER_SPAN;
pub use def::*;
pub use method::{settings_table, Method};
pub use overrides::{Overrides, RodOverrides, SoftnessOverride};

use std::path::{Path, PathBuf};

use locate::Seg;

/// A scene error located in its file.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The scene file.
    pub file: PathBuf,
    /// 1-based line of the error in the file.
    pub line: usize,
    /// Path of the offending field (empty when the error has none).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: ", self.file.display(), self.line)?;
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneError {}

/// A parsed and checked scene, with its source text (logged into recordings).
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file's path; its stem names the scene unless the file sets `name`.
    pub path: PathBuf,
    /// The scene file's text.
    pub text: String,
    /// The parsed and checked definition.
    pub def: SceneDef,
}

impl Scene {
    /// Reads and checks a scene file, then takes its `variant` (`None`: the scene as written)
    /// and applies `overrides`, checking the result.
    pub fn load_with(
        path: impl AsRef<Path>,
        variant: Option<&str>,
        overrides: &Overrides,
    ) -> anyhow::Result<Scene> {
        let path = path.as_ref();
        let mut scene = Scene::load(path)?;
        if let Some(name) = variant {
            scene = scene.variant(name)?;
        }
        overrides.apply(&mut scene.def);
        (overrides.check_on(&scene)).map_err(|m| anyhow::anyhow!("{}: {m}", path.display()))?;
        Ok(scene)
    }

    /// Reads and checks a scene file.
    pub fn load(path: impl AsRef<Path>) -> anyhow::Result<Scene> {
        let path = path.as_ref();
        let bytes = std::fs::read(path)
            .map_err(|e| anyhow::anyhow!("{}: cannot read scene file: {e}", path.display()))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
            let column = valid.iter().rev().take_while(|&&b| b != b'\n').count() + 1;
            anyhow::anyhow!(
                "{}:{line}: not UTF-8 text (a bad byte at column {column}); scene files are UTF-8 TOML",
                path.display()
            )
        })?;
        Ok(Scene::parse(path, &text)?)
    }

    /// Parses and checks scene text; `path` is used in messages only.
    pub fn parse(path: impl AsRef<Path>, text: &str) -> Result<Scene, SceneError> {
        let path = path.as_ref().to_path_buf();
        let def: SceneDef = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            let field = locate::parse(text)
                .map(|doc| locate::render(&locate::path_at(doc.get_ref(), &span)));
            SceneError {
                file: path.clone(),
                line: locate::line_of(text, span.start),
                field: field.unwrap_or_default(),
                message: tidy_serde_message(e.message()),
            }
        })?;
        let mut def = def;
        if let Some(method) = def.method {
            // the file's own keys win over its method's
            method
                .overrides_under(&locate::top_level_keys(text))
                .apply(&mut def);
        }
        for v in &mut def.variant {
            // a variant that names only a method is named after it
            v.name = v.name.take().or(v.method.map(|m| m.to_string()));
        }
        let mut scene = Scene {
            path,
            text: text.to_string(),
            def,
        };
        // the settings first: the items' checks read them (a velocity against max_speed)
        scene
            .check_method()
            .map_err(|(p, message)| scene.error_at(&p, message))?;
        // the drop block is checked before it makes its ragdolls
        if let Some(drop) = &scene.def.drop {
            bounds::check_drop(drop).map_err(|(p, message)| scene.error_at(&p, message))?;
            let (humanoids, characters) = (drop.expand(), drop.expand_characters());
            scene.def.ragdoll.extend(humanoids);
            scene.def.character.extend(characters);
        }
        // tiles are checked where they are written, then copied into `body`
        scene
            .check_tiles()
            .map_err(|(p, message)| scene.error_at(&p, message))?;
        let copies: Vec<BodyDef> = scene.def.tile.iter().flat_map(TileDef::expand).collect();
        scene.def.body.extend(copies);
        scene
            .check()
            .map_err(|(p, message)| scene.error_at(&p, message))?;
        Ok(scene)
    }

    /// Name used for the recording: `name`, or the file stem.
    pub fn name(&self) -> String {
        self.def.name.clone().unwrap_or_else(|| {
            self.path
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        })
    }

    fn error_at(&self, path: &[Seg], message: String) -> SceneError {
        let doc = locate::parse(&self.text).expect("text parsed before");
        let span = locate::span_of(&doc, path);
        SceneError {
            file: self.path.clone(),
            line: locate::line_of(&self.text, span.start),
            field: locate::render(path),
            message,
        }
    }
}

/// serde's "unknown variant `x`, expected one of `a`, `b`" reads better as
/// `unknown value "x", expected one of a, b`.
fn tidy_serde_message(message: &str) -> String {
    let message = message.trim().replace("unknown variant", "unknown value");
    let mut out = String::with_capacity(message.len());
    for (i, part) in message.split('`').enumerate() {
        if i == 1 || i == 2 {
            out.push('"'); // quotes around the user's value; the choices stay bare
        }
        out.push_str(part);
    }
    out
}
