//! A sweep's chart and series as a recording.

use std::path::Path;

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Tabs, TextDocumentView, TimeSeriesView, Vertical,
};

use super::{create_parent, APPLICATION_ID};

/// Writes a sweep's rows to `path`: the chart itself (the PNG the sweep wrote) in a 2D view,
/// and per method the log10 of the mean dislocation and the time per step against an
/// `iterations` timeline (Rerun's plots have no log axis, and the residual spans four decades).
/// The CSV and the machine go in as a text document.
pub fn save_sweep(
    path: &Path,
    scene: &str,
    rows: &[crate::sweep::SweepRow],
    machine: &str,
    chart_png: &[u8],
) -> anyhow::Result<()> {
    create_parent(path)?;
    let blueprint = sweep_blueprint();
    let builder = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(format!("{scene}_sweep"))
        .with_blueprint(blueprint);
    let rec = super::file::save(builder, path, true)?;
    rec.set_log_time_enabled(false);
    rec.log_static(
        "sweep/table",
        &rerun::TextDocument::new(format!(
            "# {scene} sweep\n\nMachine: {machine}\n\n```\n{}```\n",
            crate::sweep::to_csv(rows)
        ))
        .with_media_type(rerun::MediaType::markdown()),
    )?;
    rec.log_static(
        "sweep/chart",
        &rerun::EncodedImage::from_file_contents(chart_png.to_vec()),
    )?;
    let mut methods: Vec<&str> = rows.iter().map(|r| r.method.as_str()).collect();
    methods.dedup();
    for (index, method) in methods.iter().enumerate() {
        let [r, g, b] = crate::chart::PALETTE[index % crate::chart::PALETTE.len()];
        // `rod/exact x4` -> entity `rod/exact_x4` (no spaces in entity paths)
        let entity = method.replace(' ', "_");
        let color = rerun::Color::from_rgb(r, g, b);
        for kind in ["residual_log10", "step_us"] {
            rec.log_static(
                format!("sweep/{kind}/{entity}"),
                &rerun::SeriesLines::new()
                    .with_colors([color])
                    .with_names([*method]),
            )?;
        }
        for row in rows
            .iter()
            .filter(|row| row.method == *method && row.failed.is_none())
        {
            rec.set_time_sequence("iterations", row.settings.iterations as i64);
            if row.mean_dislocation_cm > 0.0 {
                rec.log(
                    format!("sweep/residual_log10/{entity}"),
                    &rerun::Scalars::single(row.mean_dislocation_cm.log10()),
                )?;
            }
            rec.log(
                format!("sweep/step_us/{entity}"),
                &rerun::Scalars::single(row.step_us),
            )?;
        }
    }
    super::file::finish(&rec)
}

/// The sweep recording's layout: the chart and the CSV in tabs, beside the two series by
/// iterations.
fn sweep_blueprint() -> Blueprint {
    use rerun::blueprint::Spatial2DView;
    let plots = Vertical::new([
        ContainerLike::from(
            TimeSeriesView::new("log10 mean dislocation (cm) by iterations")
                .with_origin("sweep/residual_log10"),
        ),
        ContainerLike::from(
            TimeSeriesView::new("Time per step (us) by iterations").with_origin("sweep/step_us"),
        ),
    ]);
    let left = Tabs::new([
        ContainerLike::from(
            Spatial2DView::new("Residual against time per step").with_origin("sweep/chart"),
        ),
        ContainerLike::from(TextDocumentView::new("Sweep CSV").with_origin("sweep/table")),
    ]);
    Blueprint::new(
        Horizontal::new([ContainerLike::from(left), ContainerLike::from(plots)])
            .with_column_shares([0.6, 0.4]),
    )
    .with_auto_views(false)
}
