//! The `.rrd` file a recording is written to: Rerun's encoder on a writer thread of our own,
//! so that a failed write (a full disk) ends the run at once with the OS error.
//!
//! Rerun's own `FileSink` ends its writer thread at the first failed write, while a flush may
//! already wait in its queue; that flush never answers, and neither does the shutdown of the
//! recording, which waits for it. Here the writer thread outlives a failure: it keeps taking
//! messages (and drops them), answers every flush, and the failure, with the OS error, is kept
//! for every later flush and for [`finish`]. No wait on the writer is longer than
//! [`WRITE_TIMEOUT`].

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use rerun::external::re_build_info::CrateVersion;
use rerun::external::re_log_encoding::{EncodeError, Encoder, EncodingOptions};
use rerun::log::LogMsg;
use rerun::sink::{LogSink, SinkFlushError};
use rerun::{RecordingStream, RecordingStreamBuilder};

/// The longest wait for the writer (s): a flush, or the footer at the end. A writer that takes
/// longer has stalled (a vanished network file system), and the run fails instead of hanging.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(10);

/// Messages queued for the writer, at most (as Rerun's `FileSink`): a full queue makes the
/// recording wait for the disk.
const QUEUE: usize = 1024;

/// A recording stream that writes to `path` (the footer too if `footer`), with the builder's
/// settings and blueprint. Creating the file and writing its header may fail here, with the OS
/// error.
pub fn save(
    builder: RecordingStreamBuilder,
    path: &Path,
    footer: bool,
) -> anyhow::Result<RecordingStream> {
    let (enabled, store_info, properties, batcher_config, hooks, blueprint) = builder.into_args();
    if !enabled {
        return Ok(RecordingStream::disabled()); // RERUN=off
    }
    let sink = RrdFile::create(path, footer)?;
    let rec = RecordingStream::new(
        store_info,
        properties,
        batcher_config,
        hooks,
        Box::new(sink),
    )?;
    if let Some(blueprint) = blueprint {
        blueprint.send(&rec)?;
    }
    Ok(rec)
}

/// Writes everything logged to `rec` so far and, if it writes to an [`RrdFile`], ends the file
/// (the footer) and reports the first failed write, with the OS error. Later messages are
/// dropped.
pub fn finish(rec: &RecordingStream) -> anyhow::Result<()> {
    flush(rec)?;
    let (tx, rx) = std::sync::mpsc::channel();
    rec.inspect_sink(move |sink| {
        let sink: &dyn std::any::Any = sink;
        let _ = tx.send(sink.downcast_ref::<RrdFile>().map(|f| f.shared.clone()));
    });
    let Ok(Some(shared)) = rx.recv_timeout(WRITE_TIMEOUT) else {
        return Ok(()); // not a file of ours (a viewer, stdout), or a disabled stream
    };
    // runs the sink's `finalize_deferred_in_place` (the footer), each wait in it bounded
    rec.finalize_deferred_sinks();
    match shared.failure() {
        Some(failure) => Err(write_error(&failure)),
        None => Ok(()),
    }
}

/// Flushes `rec`, at most [`WRITE_TIMEOUT`] long.
pub fn flush(rec: &RecordingStream) -> anyhow::Result<()> {
    rec.flush_with_timeout(WRITE_TIMEOUT)
        .map_err(|e| write_error(&e.to_string()))
}

fn write_error(failure: &str) -> anyhow::Error {
    anyhow::anyhow!("the recording could not be written: {failure}")
}

/// What the sink and its writer thread share.
struct Shared {
    path: PathBuf,
    /// The first failure, "writing PATH: OS error".
    failure: Mutex<Option<String>>,
}

impl Shared {
    fn failure(&self) -> Option<String> {
        self.failure
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    fn fail(&self, error: EncodeError) {
        let mut failure = self.failure.lock().unwrap_or_else(|p| p.into_inner());
        if failure.is_none() {
            let error = match error {
                EncodeError::Write(io) => io.to_string(),
                other => other.to_string(),
            };
            *failure = Some(format!("writing {}: {error}", self.path.display()));
        }
    }
}

enum Command {
    Write(LogMsg),
    /// Flush the file, then answer.
    Flush(SyncSender<()>),
}

/// A [`LogSink`] that writes an `.rrd` file on its own thread (see the module docs).
pub struct RrdFile {
    shared: Arc<Shared>,
    /// `None` once the file is closed.
    commands: Mutex<Option<SyncSender<Command>>>,
    /// Answers once the writer has ended the file.
    closed: Mutex<Option<Receiver<()>>>,
}

impl RrdFile {
    /// Creates the file and writes the stream header.
    fn create(path: &Path, footer: bool) -> anyhow::Result<Self> {
        let shared = Arc::new(Shared {
            path: path.to_path_buf(),
            failure: Mutex::new(None),
        });
        let file = File::create(path)
            .map_err(|e| anyhow::anyhow!("cannot create the recording {}: {e}", path.display()))?;
        let options = EncodingOptions::PROTOBUF_COMPRESSED;
        let mut encoder = Encoder::new_eager(CrateVersion::LOCAL, options, file).map_err(|e| {
            shared.fail(e);
            write_error(&shared.failure().unwrap_or_default())
        })?;
        if !footer {
            encoder.do_not_emit_footer();
        }
        let (commands, queue) = sync_channel(QUEUE);
        let (closed_tx, closed) = sync_channel(1);
        let writer = shared.clone();
        std::thread::Builder::new()
            .name("rrd_writer".into())
            .spawn(move || {
                write_all(encoder, &queue, &writer);
                let _ = closed_tx.send(());
            })?;
        Ok(RrdFile {
            shared,
            commands: Mutex::new(Some(commands)),
            closed: Mutex::new(Some(closed)),
        })
    }

    /// Ends the file (its footer) once the queue is written, waiting at most
    /// [`WRITE_TIMEOUT`]; later messages are dropped.
    fn close(&self) {
        drop(
            self.commands
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .take(),
        );
        let closed = self.closed.lock().unwrap_or_else(|p| p.into_inner()).take();
        if let Some(closed) = closed {
            if closed.recv_timeout(WRITE_TIMEOUT) == Err(RecvTimeoutError::Timeout) {
                let stalled = std::io::Error::other("the writer stalled");
                self.shared.fail(EncodeError::Write(stalled));
            }
        }
    }
}

/// The writer thread: every message in order until the queue closes, then the file's end.
/// After a failure it drops what comes and still answers flushes.
fn write_all(encoder: Encoder<File>, queue: &Receiver<Command>, shared: &Shared) {
    let mut writer = Writer {
        encoder: Some(encoder),
        shared,
    };
    for command in queue {
        match command {
            Command::Write(msg) => writer.attempt(|e| e.append(&msg).map(|_| ())),
            Command::Flush(done) => {
                writer.attempt(Encoder::flush_blocking);
                let _ = done.send(());
            }
        }
    }
    writer.attempt(|e| e.finish().and_then(|()| e.flush_blocking()));
    let _ = writer.encoder.take().map(Encoder::into_inner);
}

/// The writer thread's encoder, until a write fails.
struct Writer<'a> {
    encoder: Option<Encoder<File>>,
    shared: &'a Shared,
}

impl Writer<'_> {
    /// Runs `write` unless a write failed before; a failure is kept, and the encoder let go.
    fn attempt(&mut self, write: impl FnOnce(&mut Encoder<File>) -> Result<(), EncodeError>) {
        let Some(encoder) = self.encoder.as_mut() else {
            return;
        };
        if let Err(error) = write(encoder) {
            self.shared.fail(error);
            // unwrapped, so that dropping it does not try to write the footer again
            let _ = self.encoder.take().map(Encoder::into_inner);
        }
    }
}

impl LogSink for RrdFile {
    fn send(&self, msg: LogMsg) {
        let commands = self.commands.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(commands) = commands.as_ref() {
            let _ = commands.send(Command::Write(msg));
        }
    }

    fn flush_blocking(&self, timeout: Duration) -> Result<(), SinkFlushError> {
        let failed = |failure: String| Err(SinkFlushError::failed(failure));
        if let Some(failure) = self.shared.failure() {
            return failed(failure);
        }
        let (done, answer) = sync_channel(1);
        {
            let commands = self.commands.lock().unwrap_or_else(|p| p.into_inner());
            let Some(commands) = commands.as_ref() else {
                return Ok(()); // closed: written to the end
            };
            if commands.send(Command::Flush(done)).is_err() {
                return failed("the writer thread ended".into());
            }
        }
        match answer.recv_timeout(timeout.min(WRITE_TIMEOUT)) {
            Ok(()) => match self.shared.failure() {
                Some(failure) => failed(failure),
                None => Ok(()),
            },
            Err(RecvTimeoutError::Timeout) => Err(SinkFlushError::Timeout),
            Err(RecvTimeoutError::Disconnected) => failed("the writer thread ended".into()),
        }
    }

    fn defers_finalization_to_shutdown(&self) -> bool {
        true // the footer is written at the end
    }

    fn finalize_deferred_in_place(&self) -> bool {
        self.close();
        true
    }
}

impl Drop for RrdFile {
    fn drop(&mut self) {
        self.close();
    }
}
