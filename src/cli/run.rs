//! `rodlab run`: one scene into a recording (a file, a viewer, or stdout), with rows of
//! residuals as it goes; and the guards on where a recording may be written.

use std::path::Path;

use anyhow::Context as _;
use clap::{parser::ValueSource, ArgMatches};

use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::record::{self, Recorder};
use crate::scene::Scene;
use crate::sim::{self, Observer, Overrides, RunReport};
use crate::world::SimulationError;

use super::stop;
use super::summary::print_summary;

/// Whether the user chose where the recording goes (otherwise we save to recordings/).
pub(super) fn rerun_sink_given(matches: &ArgMatches) -> bool {
    ["save", "spawn", "connect", "stdout"]
        .iter()
        .any(|id| matches!(matches.value_source(id), Some(ValueSource::CommandLine)))
}

/// Refuses to write a recording over the scene file being run (under any of its names: a
/// symbolic or hard link to it too), and, unless `force`, over an existing path that is not
/// a recording of its own: a symbolic link (writing follows it), anything but a regular file,
/// a file with other hard links (writing changes them all), or a file that does not start
/// with Rerun's `.rrd` header, whatever its name. An empty file holds nothing to lose.
pub(super) fn check_output(out: &Path, scene: &Path, force: bool) -> anyhow::Result<()> {
    let refuse = |what: &str| {
        anyhow::anyhow!(
            "--save {}: {what}; pass --force to write over it",
            out.display()
        )
    };
    if same_file(out, scene) {
        anyhow::bail!(
            "--save {}: that is the scene being run; choose another file",
            out.display()
        );
    }
    let Ok(meta) = std::fs::symlink_metadata(out) else {
        return Ok(()); // nothing there yet
    };
    if force {
        return Ok(());
    }
    if meta.file_type().is_symlink() {
        return Err(refuse("it is a symbolic link, and writing would follow it"));
    }
    if !meta.is_file() {
        return Err(refuse("it exists and is not a regular file"));
    }
    if let Some(links) = hard_links(&meta).filter(|&n| n > 1) {
        return Err(refuse(&format!(
            "the file has {links} hard links, and writing would change every one"
        )));
    }
    if meta.len() > 0 && !starts_like_a_recording(out)? {
        return Err(refuse(
            "the file exists and is not an .rrd recording (no Rerun header at its start)",
        ));
    }
    Ok(())
}

/// Whether `a` and `b` name the same file (through links too).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return (a.dev(), a.ino()) == (b.dev(), b.ino());
        }
    }
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// How many names the file has, where the platform says.
fn hard_links(meta: &std::fs::Metadata) -> Option<u64> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        Some(meta.nlink())
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        None
    }
}

/// Whether the file starts with an `.rrd` stream header's magic bytes (this Rerun's or an
/// older one's).
fn starts_like_a_recording(path: &Path) -> anyhow::Result<bool> {
    use rerun::external::re_log_encoding::{OLD_RRD_FOURCC, RRD_FOURCC};
    use std::io::Read as _;
    let file = std::fs::File::open(path)
        .with_context(|| format!("--save {}: cannot read the existing file", path.display()))?;
    let mut start = Vec::with_capacity(4);
    file.take(4).read_to_end(&mut start)?;
    let magic: Option<[u8; 4]> = start.try_into().ok();
    Ok(magic.is_some_and(|m| m == RRD_FOURCC || OLD_RRD_FOURCC.contains(&m)))
}

/// Loads a scene, at its `[[variant]]` `variant` if given, with the command line's overrides.
pub fn load_scene(
    path: &Path,
    variant: Option<&str>,
    overrides: &Overrides,
) -> anyhow::Result<Scene> {
    Scene::load_with(path, variant, overrides)
}

/// Runs `scene` into a recording; the recording stays readable if the run fails.
pub fn record_scene(scene: &Scene, rec: rerun::RecordingStream) -> anyhow::Result<RunReport> {
    record_scene_from(scene, rec, 0.0)
}

/// [`record_scene`], logging only the frames at or after the simulated time `from` (s).
pub fn record_scene_from(
    scene: &Scene,
    rec: rerun::RecordingStream,
    from: f32,
) -> anyhow::Result<RunReport> {
    record_scene_to(scene, rec, from, false)
}

/// [`record_scene_from`]; `live` (a viewer watching) sends every frame as it comes instead of
/// a block per second of wall time.
fn record_scene_to(
    scene: &Scene,
    rec: rerun::RecordingStream,
    from: f32,
    live: bool,
) -> anyhow::Result<RunReport> {
    anyhow::ensure!(
        scene.def.kinematics.is_none(),
        "{}: a kinematics scene simulates nothing; record it with record_kinematics_scene",
        scene.name()
    );
    let mut lab = scene.build()?;
    let mut recorder = Recorder::new(rec, &lab, scene)?;
    recorder.live = live;
    let mut late = FromTime {
        inner: &mut recorder,
        from: from as f64 - 0.5 * scene.def.dt as f64,
    };
    let mut observer = RowPrinter {
        inner: &mut late,
        every: scene.def.report_every,
    };
    let report = sim::run(&mut lab, scene.def.frames, &mut observer)
        .with_context(|| format!("{}: simulation stopped", scene.path.display()))?;
    recorder.finish(&report)?;
    Ok(report)
}

/// Hands on the frames at or after the simulated time `from` (s) only; a failure always.
struct FromTime<'a> {
    inner: &'a mut dyn Observer,
    from: f64,
}

impl Observer for FromTime<'_> {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match lab.world.time >= self.from {
            true => self.inner.begin(lab, metrics),
            false => Ok(()),
        }
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match lab.world.time >= self.from {
            true => self.inner.frame(lab, metrics),
            false => Ok(()),
        }
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        self.inner.failed(lab, error);
    }
}

/// Prints one row of residuals per ragdoll every `every` frames, then hands on the frame.
struct RowPrinter<'a> {
    inner: &'a mut dyn Observer,
    every: u32,
}

impl Observer for RowPrinter<'_> {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        if self.every > 0 {
            report!(
                "  {:>6} {:>8} {:<14} {:>10} {:>10} {:>14}",
                "frame",
                "time s",
                "ragdoll",
                "disl. cm",
                "ang. rad",
                "pose dev. cm"
            );
        }
        self.inner.begin(lab, metrics)
    }

    fn stop_requested(&self) -> bool {
        stop::requested()
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        if self.every > 0 && lab.world.frame.is_multiple_of(self.every as u64) {
            for (ragdoll, r) in lab.ragdolls.iter().zip(&metrics.ragdolls) {
                report!(
                    "  {:>6} {:>8.3} {:<14} {:>10.4} {:>10.5} {:>14.4}",
                    lab.world.frame,
                    lab.world.time,
                    ragdoll.name,
                    r.dislocation_cm,
                    r.angular_rad,
                    r.pose_deviation_cm
                );
            }
        }
        self.inner.frame(lab, metrics)
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        self.inner.failed(lab, error)
    }
}

pub(super) fn run_one(
    scene: &Scene,
    record_from: f32,
    rerun_args: &rerun::clap::RerunArgs,
    sink_given: bool,
    save_path: Option<&Path>,
) -> anyhow::Result<()> {
    let name = scene.name();
    let (rec, _serve_guard, out) = if let Some(path) = save_path {
        // ours rather than `RerunArgs`' file sink: the same writer as the main job's
        (
            record::save_to(path, scene)?,
            Default::default(),
            Some(path.to_path_buf()),
        )
    } else if sink_given {
        let (rec, guard) =
            rerun_args.init_with_blueprint(record::APPLICATION_ID, record::blueprint(scene))?;
        (rec, guard, None)
    } else {
        let out = Path::new("recordings").join(format!("{name}.rrd"));
        note!("recording to {}", out.display());
        (record::save_to(&out, scene)?, Default::default(), Some(out))
    };
    if scene.def.kinematics.is_some() {
        return record_kinematics_scene(scene, &rec);
    }
    // no file: a viewer (--spawn, --connect) or a pipe, sent frame by frame
    let report = record_scene_to(scene, rec, record_from, out.is_none())?;
    print_summary(&name, scene, &report);
    if stop::requested() {
        report!(
            "  stopped by {} after {} of {} frames",
            stop::signal_name(),
            report.frames,
            scene.def.frames
        );
    }
    Ok(())
}

/// Records a kinematics scene (Fig. 6): the comparison computed by
/// [`Comparison`](crate::kinematics::Comparison), drawn, and its largest end gaps printed.
pub fn record_kinematics_scene(scene: &Scene, rec: &rerun::RecordingStream) -> anyhow::Result<()> {
    let k = scene
        .def
        .kinematics
        .as_ref()
        .context("not a kinematics scene")?;
    let comparison = crate::kinematics::Comparison::new(
        k.length,
        k.joints,
        &k.unequal,
        k.max_bend.to_radians(),
        scene.def.frames as usize,
    );
    record::record_kinematics(rec, scene, &comparison)?;
    let (equal, unequal) = comparison.largest_gaps();
    report!(
        "{}: {} bends recorded",
        scene.name(),
        comparison.bends.len()
    );
    report!(
        "  largest end gap from the rod: equal-angle chain {:.2} cm, unequal-angle chain {:.2} cm",
        100.0 * equal,
        100.0 * unequal
    );
    Ok(())
}
