//! Per-frame shapes buffered per entity and sent as one chunk per flush
//! (`RecordingStream::send_columns`), like the scalars in [`super::columns`].
//!
//! Logging each entity every frame made one row per entity per frame go through Rerun's
//! batcher, which cut chunks on its own clock: 25-28 chunks per entity for a 10 s drop, each
//! with its own schema and footer entry. A track is one chunk per flush, carries only the
//! fields that change (colours and radii are static), and costs one serialisation per flush
//! instead of one per frame.

use rerun::RecordingStream;

/// What a track draws, and so which fields its points go to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackKind {
    /// `Capsules3D` translations and quaternions.
    Capsules,
    /// `Ellipsoids3D` centers and quaternions.
    Ellipsoids,
    /// `Boxes3D` centers and quaternions.
    Boxes,
    /// `Points3D` positions.
    Points,
    /// `LineStrips3D`: any number of strips a frame (one per rod, or per ragdoll's bones).
    Strips,
    /// `Arrows3D` origins and vectors.
    Arrows,
}

/// One entity's changing fields since the last [`Track::send`].
pub struct Track {
    entity: String,
    kind: TrackKind,
    frames: Vec<i64>,
    times: Vec<f64>,
    /// Instances (shapes, points, arrows or strips) per frame.
    lengths: Vec<usize>,
    /// Points per strip (`Strips` only).
    strip_lengths: Vec<usize>,
    /// Translations, centers, positions, strip points or arrow vectors.
    points: Vec<[f32; 3]>,
    /// Rotations (xyzw) of capsules, ellipsoids and boxes.
    rotations: Vec<[f32; 4]>,
    /// Arrow origins.
    origins: Vec<[f32; 3]>,
}

impl Track {
    pub fn new(entity: impl Into<String>, kind: TrackKind) -> Self {
        Track {
            entity: entity.into(),
            kind,
            frames: Vec::new(),
            times: Vec::new(),
            lengths: Vec::new(),
            strip_lengths: Vec::new(),
            points: Vec::new(),
            rotations: Vec::new(),
            origins: Vec::new(),
        }
    }

    pub fn entity(&self) -> &str {
        &self.entity
    }

    /// Starts the row of `frame` (simulated `time`, s); the pushes that follow fill it.
    pub fn begin(&mut self, frame: i64, time: f64) {
        self.frames.push(frame);
        self.times.push(time);
        self.lengths.push(0);
    }

    fn count(&mut self) {
        *self.lengths.last_mut().expect("begin() before any push") += 1;
    }

    /// A position, or (with [`Self::push_pose`] and [`Self::push_arrow`]) a shape's centre or
    /// an arrow's vector.
    pub fn push_point(&mut self, p: [f32; 3]) {
        self.points.push(p);
        self.count();
    }

    /// A shape's centre and rotation (xyzw).
    pub fn push_pose(&mut self, centre: [f32; 3], rotation: [f32; 4]) {
        self.rotations.push(rotation);
        self.push_point(centre);
    }

    /// One strip through `points`, the row's next instance.
    pub fn push_strip(&mut self, points: impl IntoIterator<Item = [f32; 3]>) {
        let before = self.points.len();
        self.points.extend(points);
        self.strip_lengths.push(self.points.len() - before);
        self.count();
    }

    pub fn push_arrow(&mut self, origin: [f32; 3], vector: [f32; 3]) {
        self.origins.push(origin);
        self.push_point(vector);
    }

    /// Sends the buffered rows as one chunk on the `frame` and `sim_time` timelines, and
    /// empties the buffers.
    pub fn send(&mut self, rec: &RecordingStream) -> anyhow::Result<()> {
        if self.frames.is_empty() {
            return Ok(());
        }
        let entity = self.entity.as_str();
        let times = [
            rerun::TimeColumn::new_sequence("frame", self.frames.iter().copied()),
            rerun::TimeColumn::new_duration_secs("sim_time", self.times.iter().copied()),
        ];
        let lengths = self.lengths.iter().copied();
        let points = self.points.iter().copied();
        let rotations = (self.rotations.iter()).map(|&q| rerun::Quaternion::from_xyzw(q));
        match self.kind {
            TrackKind::Capsules => rec.send_columns(
                entity,
                times,
                rerun::Capsules3D::update_fields()
                    .with_translations(points)
                    .with_quaternions(rotations)
                    .columns(lengths)?,
            )?,
            TrackKind::Ellipsoids => rec.send_columns(
                entity,
                times,
                rerun::Ellipsoids3D::update_fields()
                    .with_centers(points)
                    .with_quaternions(rotations)
                    .columns(lengths)?,
            )?,
            TrackKind::Boxes => rec.send_columns(
                entity,
                times,
                rerun::Boxes3D::update_fields()
                    .with_centers(points)
                    .with_quaternions(rotations)
                    .columns(lengths)?,
            )?,
            TrackKind::Points => rec.send_columns(
                entity,
                times,
                rerun::Points3D::update_fields()
                    .with_positions(points)
                    .columns(lengths)?,
            )?,
            TrackKind::Arrows => rec.send_columns(
                entity,
                times,
                rerun::Arrows3D::update_fields()
                    .with_vectors(points)
                    .with_origins(self.origins.iter().copied())
                    .columns(lengths)?,
            )?,
            TrackKind::Strips => {
                let mut start = 0;
                let strips: Vec<rerun::components::LineStrip3D> = (self.strip_lengths.iter())
                    .map(|&n| {
                        start += n;
                        rerun::components::LineStrip3D::from_iter(
                            self.points[start - n..start].iter().copied(),
                        )
                    })
                    .collect();
                rec.send_columns(
                    entity,
                    times,
                    rerun::LineStrips3D::update_fields()
                        .with_strips(strips)
                        .columns(lengths)?,
                )?
            }
        }
        self.frames.clear();
        self.times.clear();
        self.lengths.clear();
        self.strip_lengths.clear();
        self.points.clear();
        self.rotations.clear();
        self.origins.clear();
        Ok(())
    }
}
