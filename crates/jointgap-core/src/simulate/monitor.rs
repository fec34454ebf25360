//! What a run tells its caller while it goes: progress reports for a display, and the
//! output samples in chunks, so that a long run can be streamed to disk instead of
//! being held in memory.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::output::Status;

/// Where a run stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Simulated time reached [s].
    pub time: f64,
    /// End time of the run [s].
    pub t_end: f64,
    /// Steps taken (accepted and rejected).
    pub steps: usize,
    /// Contact onsets so far, all clearance joints together.
    pub impacts: usize,
    /// Wall-clock time since the integration started [s].
    pub wall_time: f64,
}

/// Why a monitor stops a run; what was computed up to there is kept either way.
#[derive(Debug, Clone, PartialEq)]
pub enum Stop {
    /// The user asked for it (Ctrl-C): the run ends with [`Status::Interrupted`].
    Interrupted,
    /// Something failed on the caller's side: the run ends with [`Status::Failed`] and
    /// this reason.
    Error(String),
}

impl Stop {
    /// The status of a run stopped at `time`; `what` says who stopped it, before a reason.
    pub fn status(self, time: f64, what: &str) -> Status {
        match self {
            Stop::Interrupted => Status::Interrupted { time },
            Stop::Error(reason) => Status::Failed { time, reason: format!("{what}: {reason}") },
        }
    }
}

/// Receives a run's progress and, when it asks for them, its samples in chunks. An `Err`
/// from either method stops the run there ([`Stop`]); what was computed is kept.
pub trait Monitor {
    /// Wall-clock seconds between two progress reports (0: at every check, every 16
    /// accepted steps); `None`: no reports.
    fn progress_interval(&self) -> Option<f64> {
        None
    }

    /// A progress report, about every `progress_interval` seconds.
    fn progress(&mut self, _progress: &Progress) -> Result<(), Stop> {
        Ok(())
    }

    /// Samples per chunk handed to [`Monitor::samples`]; `None` keeps every sample in the
    /// result instead.
    fn chunk_len(&self) -> Option<usize> {
        None
    }

    /// A full chunk (the last one may be shorter): `data[k][i]` is channel `names[k]` at
    /// `time[i]`. These samples are not kept in the result.
    fn samples(&mut self, _names: &[String], _time: &[f64], _data: &[Vec<f64>]) -> Result<(), Stop> {
        Ok(())
    }
}

/// A monitor that asks for nothing: every sample stays in the result.
pub struct Silent;

impl Monitor for Silent {}

/// What the caller of a batch ([`crate::simulate_batch`]) shares with its runs while they
/// go on other threads: a stop request (Ctrl-C), which each run checks every 16 accepted
/// steps and a case not yet started sees before it starts, and the counts of cases
/// running and ended, for a progress display.
#[derive(Debug, Default)]
pub struct BatchControl {
    stop: AtomicBool,
    running: AtomicUsize,
    ended: AtomicUsize,
}

impl BatchControl {
    /// Asks every run of the batch to stop: those running end with
    /// [`Status::Interrupted`] and what they computed, those not started do not start.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Whether [`BatchControl::stop`] was called.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// Cases running now.
    pub fn running(&self) -> usize {
        self.running.load(Ordering::Relaxed)
    }

    /// Cases ended (finished, failed, refused or interrupted).
    pub fn ended(&self) -> usize {
        self.ended.load(Ordering::Relaxed)
    }

    /// Counts one case from its start to its end around `run`.
    pub(crate) fn case<T>(&self, run: impl FnOnce() -> T) -> T {
        self.running.fetch_add(1, Ordering::Relaxed);
        let out = run();
        self.running.fetch_sub(1, Ordering::Relaxed);
        self.ended.fetch_add(1, Ordering::Relaxed);
        out
    }
}

/// The monitor of each run of a batch: checks the stop request at every check (every 16
/// accepted steps), with no display.
impl Monitor for &BatchControl {
    fn progress_interval(&self) -> Option<f64> {
        Some(0.0)
    }

    fn progress(&mut self, _progress: &Progress) -> Result<(), Stop> {
        if self.stopped() {
            Err(Stop::Interrupted)
        } else {
            Ok(())
        }
    }
}
