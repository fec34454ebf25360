//! What a run tells its caller while it goes: progress reports for a display, and the
//! output samples in chunks, so that a long run can be streamed to disk instead of
//! being held in memory.

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
