//! Scalars buffered per entity and sent as columns (`RecordingStream::send_columns`) at each
//! flush: one call per series per block instead of one `log` per value per frame, which was
//! most of what recording cost a frame.
//!
//! A series may be several wide: one instance per ragdoll (or rod) in one entity, which the
//! viewer plots as one named line each. Every row costs a row id and two time stamps (32
//! bytes) beside each 8-byte value, so one entity per ragdoll made most of a 30-ragdoll
//! recording's scalar bytes.

use std::collections::HashMap;

use rerun::RecordingStream;

struct Series {
    entity: String,
    width: usize,
    frames: Vec<i64>,
    times: Vec<f64>,
    /// `width` values per frame; NaN (a gap in the plot) where none was set.
    values: Vec<f64>,
}

/// Every scalar series of a recording, buffered since the last [`ScalarColumns::send`].
#[derive(Default)]
pub struct ScalarColumns {
    index: HashMap<String, usize>,
    series: Vec<Series>,
    frame: i64,
    time: f64,
}

impl ScalarColumns {
    /// The frame (and simulated time, s) the next values belong to.
    pub fn at(&mut self, frame: i64, time: f64) {
        (self.frame, self.time) = (frame, time);
    }

    /// The id of `entity`'s series, `width` values a frame (created on first use).
    pub fn series(&mut self, entity: &str, width: usize) -> usize {
        if let Some(&i) = self.index.get(entity) {
            return i;
        }
        self.index.insert(entity.to_string(), self.series.len());
        self.series.push(Series {
            entity: entity.to_string(),
            width,
            frames: Vec::new(),
            times: Vec::new(),
            values: Vec::new(),
        });
        self.series.len() - 1
    }

    /// Value `instance` of series `id` at the current frame.
    pub fn set(&mut self, id: usize, instance: usize, value: f64) {
        let s = &mut self.series[id];
        if s.frames.last() != Some(&self.frame) {
            s.frames.push(self.frame);
            s.times.push(self.time);
            s.values.extend(std::iter::repeat_n(f64::NAN, s.width));
        }
        let row = s.values.len() - s.width;
        s.values[row + instance] = value;
    }

    /// One value of `entity`'s single-valued series at the current frame.
    pub fn push(&mut self, entity: &str, value: f64) {
        let id = self.series(entity, 1);
        self.set(id, 0, value);
    }

    /// Sends every series' buffered values as one chunk each, on the `frame` and `sim_time`
    /// timelines, and empties the buffers.
    pub fn send(&mut self, rec: &RecordingStream) -> anyhow::Result<()> {
        for s in self.series.iter_mut().filter(|s| !s.values.is_empty()) {
            rec.send_columns(
                s.entity.as_str(),
                [
                    rerun::TimeColumn::new_sequence("frame", s.frames.iter().copied()),
                    rerun::TimeColumn::new_duration_secs("sim_time", s.times.iter().copied()),
                ],
                rerun::Scalars::new(s.values.iter().copied())
                    .columns(std::iter::repeat_n(s.width, s.frames.len()))?,
            )?;
            s.frames.clear();
            s.times.clear();
            s.values.clear();
        }
        Ok(())
    }
}
