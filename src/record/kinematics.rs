//! The kinematics comparison (Fig. 6) drawn: the end loci, the spines at each bend, the gaps.
//! The geometry is computed in [`crate::kinematics::Comparison`].

use rerun::RecordingStream;

use crate::kinematics::Comparison;
use crate::scene::Scene;

/// Records the kinematics comparison (Fig. 6) of `scene`: the three end loci as static line
/// strips, and per frame the three spines at one bend with the end gaps.
pub fn record_kinematics(
    rec: &RecordingStream,
    scene: &Scene,
    comparison: &Comparison,
) -> anyhow::Result<()> {
    rec.set_log_time_enabled(false);
    rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
    let text = format!("# {}\n\n```toml\n{}\n```\n", scene.name(), scene.text);
    rec.log_static("scene", &rerun::TextDocument::from_markdown(text))?;
    let colors = [
        rerun::Color::from_rgb(60, 110, 220),
        rerun::Color::from_rgb(60, 170, 90),
        rerun::Color::from_rgb(220, 60, 50),
    ];
    for ((name, shapes), color) in comparison.spines.iter().zip(colors) {
        let locus: Vec<[f32; 3]> = shapes
            .iter()
            .map(|points| points.last().expect("a spine has points").to_array())
            .collect();
        rec.log_static(
            format!("world/locus/{name}"),
            &rerun::LineStrips3D::new([locus])
                .with_colors([color])
                .with_radii([0.002]),
        )?;
    }
    for (i, psi) in comparison.bends.iter().enumerate() {
        rec.set_time_sequence("frame", i as i64);
        rec.set_duration_secs("sim_time", i as f64 * scene.def.dt as f64);
        for (s, ((name, shapes), color)) in comparison.spines.iter().zip(colors).enumerate() {
            rec.log(
                format!("world/spine/{name}"),
                &rerun::LineStrips3D::new([shapes[i].iter().map(|p| p.to_array())])
                    .with_colors([color])
                    .with_radii([0.006]),
            )?;
            if *name != "rod" {
                rec.log(
                    format!("metrics/end_gap_cm/{name}"),
                    &rerun::Scalars::single(100.0 * comparison.end_gap(s, i) as f64),
                )?;
            }
        }
        rec.log("metrics/bend_rad", &rerun::Scalars::single(*psi as f64))?;
    }
    super::file::finish(rec)
}
