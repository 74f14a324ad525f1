//! Scalars buffered per entity and sent as columns (`RecordingStream::send_columns`) at each
//! flush: one call per series per block instead of one `log` per value per frame, which was
//! most of what recording cost a frame.

use std::collections::HashMap;

use rerun::RecordingStream;

struct Series {
    entity: String,
    frames: Vec<i64>,
    times: Vec<f64>,
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

    /// One value of `entity`'s series at the current frame.
    pub fn push(&mut self, entity: &str, value: f64) {
        let i = match self.index.get(entity) {
            Some(&i) => i,
            None => {
                self.index.insert(entity.to_string(), self.series.len());
                self.series.push(Series {
                    entity: entity.to_string(),
                    frames: Vec::new(),
                    times: Vec::new(),
                    values: Vec::new(),
                });
                self.series.len() - 1
            }
        };
        let s = &mut self.series[i];
        s.frames.push(self.frame);
        s.times.push(self.time);
        s.values.push(value);
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
                rerun::Scalars::new(s.values.iter().copied()).columns_of_unit_batches()?,
            )?;
            s.frames.clear();
            s.times.clear();
            s.values.clear();
        }
        Ok(())
    }
}
