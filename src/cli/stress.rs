//! `rodlab stress`: the stress suite, its table, and recordings of the runs that failed.

use std::path::{Path, PathBuf};

use anyhow::Context as _;

use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::record::{self, Recorder, RecordingInfo};
use crate::scene::RecordDef;
use crate::sim::Observer;
use crate::world::SimulationError;

use super::sweep::Progress;

/// `rodlab stress`: the suite, its table printed and saved, failing runs' recordings kept.
pub(super) fn stress(out: &Path) -> anyhow::Result<()> {
    use crate::stress::{self, Method, Verdict};
    let folder = out.join("stress");
    std::fs::create_dir_all(&folder)
        .with_context(|| format!("cannot create {}", folder.display()))?;
    let cases = stress::suite();
    let started = std::time::Instant::now();
    let mut outcomes = Vec::new();
    let mut kept = Vec::new();
    let mut progress = Progress::new(cases.len() * Method::ALL.len());
    for case in &cases {
        for method in Method::ALL {
            progress.show(&format!("{} {method}", case.name));
            let name = format!("{}_{method}", case.name);
            let path = folder.join(format!("{name}.rrd"));
            // every run is recorded; a stable run's file is deleted afterwards
            let info = RecordingInfo {
                name: format!("stress_{name}"),
                about: format!(
                    "`rodlab stress`, case {}, {method}: {}\n",
                    case.name, case.description
                ),
                kinematics: false,
                options: RecordDef::default(),
            };
            let mut recorder = LazyRecorder {
                path: path.clone(),
                info,
                recorder: None,
            };
            let outcome = stress::run_case(case, method, &mut recorder)?;
            drop(recorder);
            match outcome {
                Some(outcome) if outcome.verdict != Verdict::Stable => {
                    kept.push(path);
                    outcomes.push(outcome);
                }
                Some(outcome) => {
                    std::fs::remove_file(&path).ok();
                    outcomes.push(outcome);
                }
                None => {
                    std::fs::remove_file(&path).ok();
                }
            }
        }
    }
    progress.finish();
    let markdown = stress::table_markdown(&outcomes);
    report!(
        "== stress: {} runs in {:.1} s",
        outcomes.len(),
        started.elapsed().as_secs_f32()
    );
    report!("{markdown}");
    let md_path = out.join("stress.md");
    let csv_path = out.join("stress.csv");
    let machine = crate::machine::name();
    std::fs::write(
        &md_path,
        format!("# rodlab stress suite\n\nMachine: {machine}. Criteria: docs/lab.md, \"where methods fail\".\n\n{markdown}"),
    )
    .with_context(|| format!("cannot write {}", md_path.display()))?;
    std::fs::write(&csv_path, stress::table_csv(&outcomes))
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    report!(
        "  -> {}, {}, and {} recordings of the runs that are not stable in {}",
        md_path.display(),
        csv_path.display(),
        kept.len(),
        folder.display()
    );
    Ok(())
}

/// Opens its recording when the run begins, since the stress cases build their own worlds.
struct LazyRecorder {
    path: PathBuf,
    info: RecordingInfo,
    recorder: Option<Recorder>,
}

impl Observer for LazyRecorder {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let rec = record::save_to(&self.path, self.info.clone())?;
        let recorder = self
            .recorder
            .insert(Recorder::new(rec, lab, self.info.clone())?);
        recorder.begin(lab, metrics)
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match &mut self.recorder {
            Some(recorder) => recorder.frame(lab, metrics),
            None => Ok(()),
        }
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        if let Some(recorder) = &mut self.recorder {
            recorder.failed(lab, error);
        }
    }
}
