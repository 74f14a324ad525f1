//! Recording to Rerun: the only module that uses `rerun`.
//!
//! Entity paths (documented in docs/recording.md):
//! - `world/<group>/capsules|spheres|boxes`: one batched archetype per group (`ragdolls`, every
//!   ragdoll's bodies as instances of one entity; `loose` for a scene's own bodies when it has
//!   joints or rods, measured like a ragdoll; `fixed` for bodies that never move, drawn once;
//!   else `props`); shapes logged once as static data, per-instance translations and
//!   quaternions every frame;
//! - `world/<group>/joints`: both world anchors of every joint (Points3D, 2 per joint);
//! - `world/<group>/rods/centerlines` (LineStrips3D, a strip per rod through gamma(s), ends at
//!   the body centres) and `.../rods/frames` (Arrows3D: material normal and binormal along
//!   each arc);
//! - `world/<group>/bones/<method>`: the animation bones, a strip per ragdoll through their
//!   origins;
//! - `metrics/dislocation_cm`, `metrics/angular_rad`, `metrics/pose_deviation_cm`: residual
//!   scalars, one entity per measure with one instance (a named line) per ragdoll, so spines
//!   compare in one plot;
//! - `metrics/rod` (psi, tau, length and curve violation: a line per rod each),
//!   `metrics/bones` (length error and chest gap: a line per ragdoll and method each),
//!   `metrics/energy` (kinetic, potential, total; J), `metrics/total` (residuals summed over the
//!   ragdolls), `metrics/contact_depth_cm` (penetration at the solver's points, overlap found
//!   afresh): one entity per plot;
//! - `metrics/awake_bodies`: dynamic bodies awake, with sleeping on (sleeping bodies are drawn
//!   in their colour faded toward grey);
//! - `scene`: the scene file (static), `failure`: why a run stopped early, if it did,
//!   `state_hash`: the final state's hash (static text, 16 hex digits) after a whole run.
//!
//! Timelines: `frame` (sequence, 0 = initial state) and `sim_time` (seconds).
//!
//! Per-frame data is buffered and sent once a second of wall time, one chunk per entity
//! (`recorder`, `tracks`, `columns`); static data is logged once. The number of entities does
//! not grow with the number of ragdolls: the file's footer keeps a manifest row per chunk in
//! memory until the end of the run.

use std::path::Path;

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextDocumentView, TimeSeriesView,
    Vertical,
};
use rerun::RecordingStream;

use crate::scene::{RecordDef, Scene};

mod bodies;
mod columns;
pub mod file;
mod kinematics;
mod recorder;
mod style;
mod sweep;
mod tracks;
pub mod tune;

pub use kinematics::record_kinematics;
pub use recorder::Recorder;
pub use sweep::save_sweep;

/// What a recording says about where it came from, apart from the lab it draws: enough to
/// record a lab built in code (the stress suite's cases) as well as one built from a scene file.
#[derive(Clone, Debug)]
pub struct RecordingInfo {
    /// Recording name (the viewer's title, and the heading of the `scene` text).
    pub name: String,
    /// Markdown shown under the name in the viewer's "Scene file" tab: the scene file's path
    /// and text, or what built the lab.
    pub about: String,
    /// The plot layout: the Fig. 6 comparison's (end gaps) or a simulation's (residuals).
    pub kinematics: bool,
    /// The `[record]` options: what to log, how often, and whether to write a footer.
    pub options: RecordDef,
}

impl From<&Scene> for RecordingInfo {
    fn from(scene: &Scene) -> Self {
        RecordingInfo {
            name: scene.name(),
            about: format!(
                "`{}`\n\n```toml\n{}\n```\n",
                scene.path.display(),
                scene.text
            ),
            kinematics: scene.def.kinematics.is_some(),
            options: scene.def.record.clone(),
        }
    }
}

/// Application id of every rodlab recording.
pub const APPLICATION_ID: &str = "rodlab";

/// Flush the sink once this much wall time (s) has passed since the last flush, so a killed
/// run loses at most the last second of its work. Each flush cuts a chunk per entity, and the
/// file's footer keeps a manifest row per chunk in memory until the end: a flush per simulated
/// second instead made a fast run's memory grow with its length (the drop runs about 3x faster
/// than real time).
const FLUSH_WALL_S: f64 = 1.0;
/// The layout for a recording: the 3D view beside its plots (residuals, then tabs for energy,
/// pose deviation, rod scalars and bone errors; for the kinematics scene, the end gaps).
pub fn blueprint(info: impl Into<RecordingInfo>) -> Blueprint {
    let info = info.into();
    let series = |name: &str, origin: &str| {
        ContainerLike::from(TimeSeriesView::new(name).with_origin(origin))
    };
    let plots = if info.kinematics {
        Vertical::new([
            series("End gap from the rod (cm)", "metrics/end_gap_cm"),
            series("Bend (rad)", "metrics/bend_rad"),
        ])
    } else {
        let more = Tabs::new([
            series("Energy (J)", "metrics/energy"),
            series("Pose deviation (cm)", "metrics/pose_deviation_cm"),
            series("Rod", "metrics/rod"),
            series("Bones (cm)", "metrics/bones"),
            series("Totals", "metrics/total"),
            series("Contact depth (cm)", "metrics/contact_depth_cm"),
            series("Awake bodies", "metrics/awake_bodies"),
        ]);
        Vertical::new([
            series("Dislocation (cm)", "metrics/dislocation_cm"),
            series("Angular violation (rad)", "metrics/angular_rad"),
            ContainerLike::from(more),
        ])
    };
    let left = Tabs::new([
        ContainerLike::from(Spatial3DView::new("Scene").with_origin("world")),
        ContainerLike::from(TextDocumentView::new("Scene file").with_origin("scene")),
    ]);
    Blueprint::new(
        Horizontal::new([ContainerLike::from(left), ContainerLike::from(plots)])
            .with_column_shares([0.6, 0.4]),
    )
    .with_auto_views(false)
}

/// Creates the folder `path` will be written in, if it has one.
fn create_parent(path: &Path) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    Ok(())
}

/// Opens a recording (of a scene, or described by a [`RecordingInfo`]) that writes to `path`
/// (creating its folder), with its blueprint (and the footer unless `[record] footer = false`).
pub fn save_to(path: &Path, info: impl Into<RecordingInfo>) -> anyhow::Result<RecordingStream> {
    let info = info.into();
    create_parent(path)?;
    let footer = info.options.footer;
    let builder = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(info.name.clone())
        .with_blueprint(blueprint(info));
    file::save(builder, path, footer)
}
