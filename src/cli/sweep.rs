//! `rodlab sweep`: every method combination of a scene (and a peer engine's), into CSV, a
//! chart and a recording; and the cost of each modelled feature.

use std::path::Path;

use anyhow::Context as _;

use crate::record;
use crate::scene::Scene;
use crate::shard::Shard;
use crate::sim::Overrides;

use super::run::record_scene_from;

/// `rodlab sweep`: every combination, with a progress bar, into CSV, SVG and a recording.
pub(super) fn sweep(
    path: &Path,
    config: &crate::sweep::SweepConfig,
    peer: Option<&str>,
    shard: Shard,
    out: &Path,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    use crate::sweep;
    check_peer(peer)?;
    let scene = Scene::load(path)?;
    let name = scene.name();
    let all = sweep::combinations(&scene.def, config);
    let first_peer = all.len();
    let combinations: Vec<Overrides> = (all.into_iter().enumerate())
        .filter(|(i, _)| shard.takes(*i))
        .map(|(_, o)| o)
        .collect();
    // every combination within the scene's bounds before the first run
    for overrides in &combinations {
        let mut applied = scene.clone();
        overrides.apply(&mut applied.def);
        (overrides.check_on(&applied)).map_err(|m| anyhow::anyhow!("{}: {m}", path.display()))?;
    }
    let machine = crate::machine::name();
    let peer_runs = if peer.is_some() {
        let count = peer_iterations(config).len() * config.settings.dt.len().max(1);
        (first_peer..first_peer + count)
            .filter(|&i| shard.takes(i))
            .count()
    } else {
        0
    };
    let runs = combinations.len() + peer_runs;
    let of = if shard == Shard::ALL {
        String::new()
    } else {
        format!(" (shard {}/{})", shard.index, shard.count)
    };
    report!("== sweep {name}: {runs} runs on {machine}{of}");
    let mut progress = Progress::new(runs);
    let mut rows = Vec::with_capacity(combinations.len());
    for overrides in &combinations {
        let block = match overrides.rod.bend_twist {
            Some(crate::constraint::BendTwist::Block) => " block",
            _ => "",
        };
        progress.show(&format!(
            "{}/{}{block} {} dt={:.4} substeps={} warm={} soft={}Hz stack={} detect={} sweeps={} \
             iterations={}",
            overrides.spine.unwrap_or_default(),
            overrides.joint_flavour.unwrap_or_default(),
            overrides.solver.unwrap_or(scene.def.solver),
            overrides.dt.unwrap_or(scene.def.dt),
            overrides.substeps.unwrap_or(scene.def.substeps),
            (overrides.contact_warm_start).unwrap_or(scene.def.contact_warm_start),
            (overrides.contact_hertz).unwrap_or(scene.def.contact_hertz),
            (overrides.contact_stacking).unwrap_or(scene.def.contact_stacking),
            (overrides.contact_detection).unwrap_or(scene.def.contact_detection),
            (overrides.contact_extra_sweeps).unwrap_or(scene.def.contact_extra_sweeps),
            overrides.iterations.unwrap_or(scene.def.iterations)
        ));
        rows.push(sweep::run_one(&scene, overrides, config.repeats)?);
    }
    if peer.is_some() {
        rows.extend(peer_rows(
            &scene,
            config,
            (first_peer, shard),
            &mut progress,
        )?);
    }
    progress.finish();
    print_rows(&rows);
    write_outputs(
        &name,
        &rows,
        &machine,
        &format!("{name}_sweep{}", shard.suffix()),
        out,
    )?;
    if shard.index == 1 {
        feature_costs(&scene, out)?;
    } else {
        report!("  (the feature costs are measured by shard 1)");
    }
    Ok(rows)
}

/// Refuses a peer engine this build cannot run.
fn check_peer(peer: Option<&str>) -> anyhow::Result<()> {
    match peer {
        None => {}
        Some("rapier") if cfg!(feature = "rapier") => {}
        Some("rapier") => anyhow::bail!(
            "--peer rapier: this rodlab was built without the Rapier peer; run \
             `cargo run --release --features rapier -- sweep ...`"
        ),
        Some(other) => anyhow::bail!("--peer {other}: unknown peer engine (known: rapier)"),
    }
    Ok(())
}

/// The sweep's table on stdout, a line per run.
fn print_rows(rows: &[crate::sweep::SweepRow]) {
    report!(
        "  {:<36} {:>8} {:>4} {:>5} {:>10} {:>12} {:>12} {:>10} {:>10}",
        "method",
        "dt",
        "sub",
        "iter",
        "step us",
        "mean disl cm",
        "max disl cm",
        "mean rad",
        "overlap cm"
    );
    for r in rows {
        match &r.failed {
            None => report!(
                "  {:<36} {:>8.4} {:>4} {:>5} {:>10.1} {:>12.4} {:>12.4} {:>10.5} {:>10.2}",
                r.method,
                r.settings.dt,
                r.settings.substeps,
                r.settings.iterations,
                r.step_us,
                r.mean_dislocation_cm,
                r.max_dislocation_cm,
                r.mean_angular_rad,
                r.max_overlap_cm
            ),
            Some(e) => report!(
                "  {:<36} {:>8.4} {:>4} {:>5} failed: {e}",
                r.method,
                r.settings.dt,
                r.settings.substeps,
                r.settings.iterations
            ),
        }
    }
}

/// `rodlab merge`: the shards' CSVs (all N of one sweep, in any order) back into the whole
/// sweep's rows, then its outputs as an unsharded run writes them.
pub(super) fn merge(files: &[std::path::PathBuf], machine: &str, out: &Path) -> anyhow::Result<()> {
    let mut shards: Vec<(Shard, &std::path::PathBuf)> = Vec::new();
    let mut base: Option<String> = None;
    for file in files {
        let stem = file
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default();
        let (stem_base, shard) = Shard::from_stem(stem).with_context(|| {
            format!(
                "{}: not a sweep shard's table (<name>_sweep_shardIofN.csv)",
                file.display()
            )
        })?;
        match &base {
            Some(b) if b != stem_base => anyhow::bail!(
                "{}: a shard of {stem_base}, the others are of {b}",
                file.display()
            ),
            _ => base = Some(stem_base.to_string()),
        }
        shards.push((shard, file));
    }
    shards.sort_by_key(|(shard, _)| shard.index);
    let count = shards[0].0.count;
    let indices: Vec<usize> = shards.iter().map(|(s, _)| s.index).collect();
    anyhow::ensure!(
        shards.iter().all(|(s, _)| s.count == count) && indices == (1..=count).collect::<Vec<_>>(),
        "the shards given are {:?}; a merge needs each of 1 to {count} of {count} once",
        shards
            .iter()
            .map(|(s, _)| format!("{}of{}", s.index, s.count))
            .collect::<Vec<_>>()
    );
    let mut tables = Vec::new();
    for (_, file) in &shards {
        let text = std::fs::read_to_string(file)
            .with_context(|| format!("cannot read {}", file.display()))?;
        let rows = crate::sweep::parse_csv(&text).with_context(|| file.display().to_string())?;
        tables.push(rows);
    }
    let rows = crate::shard::interleave(tables).map_err(anyhow::Error::msg)?;
    let stem = base.expect("one shard at least");
    let name = stem.strip_suffix("_sweep").unwrap_or(&stem).to_string();
    report!("== merged {count} shards of {name}: {} runs", rows.len());
    print_rows(&rows);
    write_outputs(&name, &rows, machine, &stem, out)
}

/// `<out>/<stem>.csv`, `.svg`, `.png` and `.rrd` of the sweep's rows.
fn write_outputs(
    name: &str,
    rows: &[crate::sweep::SweepRow],
    machine: &str,
    stem: &str,
    out: &Path,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let csv = out.join(format!("{stem}.csv"));
    std::fs::write(&csv, crate::sweep::to_csv(rows))
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let svg = out.join(format!("{stem}.svg"));
    let chart = crate::sweep::chart(name, rows, machine);
    std::fs::write(&svg, chart.to_svg())
        .with_context(|| format!("cannot write {}", svg.display()))?;
    let png = out.join(format!("{stem}.png"));
    let png_bytes = chart.to_png()?;
    std::fs::write(&png, &png_bytes).with_context(|| format!("cannot write {}", png.display()))?;
    let rrd = out.join(format!("{stem}.rrd"));
    record::save_sweep(&rrd, name, rows, machine, &png_bytes)?;
    report!(
        "  -> {}, {} (and .png), {}",
        csv.display(),
        svg.display(),
        rrd.display()
    );
    // with contacts, the deepest overlap against time too: where a method lets shapes sink
    if let Some(chart) = crate::sweep::overlap_chart(name, rows, machine) {
        let svg = out.join(format!("{stem}_overlap.svg"));
        std::fs::write(&svg, chart.to_svg())
            .with_context(|| format!("cannot write {}", svg.display()))?;
        let png = out.join(format!("{stem}_overlap.png"));
        std::fs::write(&png, chart.to_png()?)
            .with_context(|| format!("cannot write {}", png.display()))?;
        report!("  -> {} (and .png)", svg.display());
    }
    Ok(())
}

/// The peer's rows: the scene with chain3 spines (Rapier has no rod), per time step and
/// iteration count (Rapier's `num_solver_iterations`).
#[cfg(feature = "rapier")]
fn peer_rows(
    scene: &Scene,
    config: &crate::sweep::SweepConfig,
    (first_index, shard): (usize, Shard),
    progress: &mut Progress,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    let mut index = first_index;
    let dts = if config.settings.dt.is_empty() {
        vec![scene.def.dt]
    } else {
        config.settings.dt.clone()
    };
    let mut rows = Vec::new();
    for dt in dts {
        for iterations in peer_iterations(config) {
            index += 1;
            if !shard.takes(index - 1) {
                continue;
            }
            progress.show(&format!("rapier dt={dt:.4} iterations={iterations}"));
            let mut peer_scene = scene.clone();
            Overrides {
                spine: Some(crate::ragdoll::SpineKind::Chain3),
                dt: Some(dt),
                frames: config.frames,
                ..Default::default()
            }
            .apply(&mut peer_scene.def);
            let mut row = crate::peer::run(&peer_scene, iterations, config.repeats)?;
            row.method = format!("{}/{}", row.method, row.spine);
            rows.push(row);
        }
    }
    Ok(rows)
}

#[cfg(not(feature = "rapier"))]
fn peer_rows(
    _: &Scene,
    _: &crate::sweep::SweepConfig,
    _: (usize, Shard),
    _: &mut Progress,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    anyhow::bail!("--peer rapier: built without the feature `rapier`")
}

/// What each modelled feature costs the scene, recording included -> <scene>_features.csv.
fn feature_costs(scene: &Scene, out: &Path) -> anyhow::Result<()> {
    let frames = scene.def.frames.min(300);
    let mut costs = crate::sweep::feature_costs(scene, frames)?;
    // recording: a whole run recorded against the same run (measured and printed alike, the
    // file opened, its static data written and closed) that records no frame
    let mut short = scene.clone();
    short.def.frames = frames;
    let scratch = std::env::temp_dir().join(format!("rodlab_cost_{}.rrd", scene.name()));
    let time_run = |from: f32| -> anyhow::Result<f64> {
        let started = std::time::Instant::now();
        record_scene_from(&short, record::save_to(&scratch, &short)?, from)?;
        Ok(started.elapsed().as_secs_f64() * 1e6 / frames as f64)
    };
    let headless = time_run(f32::INFINITY)?;
    let recorded = time_run(0.0)?;
    std::fs::remove_file(&scratch).ok();
    costs.push(crate::sweep::FeatureCost {
        feature: "recording (whole frame)",
        modelled: true,
        with_us: recorded,
        without_us: headless,
    });
    report!("  what the scene pays for (median us per frame over {frames} frames):");
    report!(
        "  {:<26} {:>9} {:>10} {:>10} {:>8}",
        "feature",
        "modelled",
        "with",
        "without",
        "cost"
    );
    for c in &costs {
        report!(
            "  {:<26} {:>9} {:>10.1} {:>10.1} {:>+7.0}%",
            c.feature,
            if c.modelled { "yes" } else { "no" },
            c.with_us,
            c.without_us,
            100.0 * (c.with_us / c.without_us - 1.0)
        );
    }
    let csv = crate::csv_table::to_text(
        "feature,modelled,with_us,without_us",
        costs.iter().map(|c| {
            vec![
                c.feature.to_string(),
                c.modelled.to_string(),
                format!("{:.3}", c.with_us),
                format!("{:.3}", c.without_us),
            ]
        }),
    );
    let path = out.join(format!("{}_features.csv", scene.name()));
    std::fs::write(&path, csv).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// A one-line progress bar on a terminal; one line per run otherwise (CI logs).
pub(super) struct Progress {
    total: usize,
    done: usize,
    terminal: bool,
    started: std::time::Instant,
}

impl Progress {
    pub(super) fn new(total: usize) -> Self {
        use std::io::IsTerminal as _;
        Progress {
            total,
            done: 0,
            terminal: std::io::stderr().is_terminal(),
            started: std::time::Instant::now(),
        }
    }

    pub(super) fn show(&mut self, label: &str) {
        const WIDTH: usize = 30;
        let filled = WIDTH * self.done / self.total.max(1);
        let bar = format!("[{}{}]", "#".repeat(filled), "-".repeat(WIDTH - filled));
        let line = format!(
            "{bar} {}/{} {:>5.1} s  {label}",
            self.done + 1,
            self.total,
            self.started.elapsed().as_secs_f32()
        );
        if self.terminal {
            use std::io::Write as _;
            let _ = write!(std::io::stderr().lock(), "\r\x1b[2K{line}");
        } else {
            note!("{line}");
        }
        self.done += 1;
    }

    pub(super) fn finish(&self) {
        if self.terminal {
            note!("");
        }
        note!(
            "  {} runs in {:.1} s",
            self.total,
            self.started.elapsed().as_secs_f32()
        );
    }
}

/// The peer's iteration counts: the sweep's, or its default list.
fn peer_iterations(config: &crate::sweep::SweepConfig) -> Vec<u32> {
    match config.settings.iterations.is_empty() {
        true => crate::sweep::DEFAULT_ITERATIONS.to_vec(),
        false => config.settings.iterations.clone(),
    }
}
