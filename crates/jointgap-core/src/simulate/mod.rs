//! One run: the model compiled and assembled, the equations of motion integrated
//! between input corners with contact events and method switching, and the output
//! recorded.

pub mod all_defaults;
pub mod any;
pub mod energy;
pub mod equations;
pub mod events;
pub mod integrate;
mod kind;
pub mod measures;
pub mod monitor;
mod options;
mod planar_channels;
pub mod record;
mod spatial_channels;
pub mod switching;
pub mod wear;

pub use kind::Kind;
pub use monitor::{BatchControl, Monitor, Progress, Silent, Stop};
pub use options::{Method, SimOptions};
pub use wear::WearOptions;

use crate::dynamics::{self, assembly};
use crate::mechanics::contact::ClearanceJoint;
use crate::mechanics::planar::Planar;
use crate::mechanics::spatial::kind::Spatial;
use crate::model::spatial::SpatialModel;
use crate::output::{RunStats, SimResult, Status};
use crate::profile::Profile;
use crate::system::System;
use crate::{Error, Model};

/// A system with consistent initial conditions, ready to integrate.
pub struct Prepared<K: Kind = Planar> {
    /// The compiled mechanism (warnings include removed redundant rows).
    pub system: System<K>,
    /// Consistent initial state.
    pub initial: assembly::Assembled,
}

/// Checks and compiles a model and assembles its initial configuration; rejects an
/// assembled state that no physical mechanism has (a clearance joint's journal deep in
/// its bearing wall).
pub fn prepare(model: &Model) -> Result<Prepared, Error> {
    prepare_model::<Planar>(model)
}

/// [`prepare`] of a model of any body kind.
pub fn prepare_model<K: Kind>(model: &K::Model) -> Result<Prepared<K>, Error> {
    let mut system = K::compile(model)?;
    let magnitudes = K::magnitude_warnings(model, &system);
    system.warnings.extend(magnitudes);
    check_weights(&system)?;
    let initial = assembly::assemble(&system)?;
    for c in &system.clearances {
        let [i, j] = c.parts().map(|b| system.body_state(b, &initial.q, &initial.v));
        c.check_initial_penetration(&i, &j)?;
    }
    system.warnings.extend(initial.warnings.iter().cloned());
    Ok(Prepared { system, initial })
}

/// Checks a model as far as a run goes before its first step: compiled, assembled, and
/// every channel a run can record (energy accounts included) evaluated at t = 0, with the
/// run's own finiteness check, so that a model a run would refuse is refused here with
/// the same error ([`initial_overflow`]). Returns the model's warnings.
pub fn check(model: &Model) -> Result<Vec<String>, Error> {
    check_prepared(&prepare(model)?)
}

/// [`check`] of a model already prepared.
pub fn check_prepared<K: Kind>(Prepared { system, initial }: &Prepared<K>) -> Result<Vec<String>, Error> {
    let mut ws = dynamics::Workspace::new(system, initial.active.clone());
    let mut rec = record::Recorder::new(system, &ws, None, 1, true)?;
    if !record_initial(system, &mut ws, &mut rec, &initial.q, &initial.v)? {
        return Err(Error::Assembly(SINGULAR_AT_START.into()));
    }
    Ok(system.warnings.clone())
}

/// Why a run whose constraint equations are singular in its initial state stops there.
const SINGULAR_AT_START: &str = "the constraint equations are singular at t = 0";

/// Records the initial state (t = 0), a run's first sample. A non-finite channel there is
/// a model error ([`initial_overflow`]); `Ok(false)` when the constraint equations are
/// singular there (a run then fails at t = 0 with what it has).
fn record_initial<K: Kind>(
    system: &System<K>,
    ws: &mut dynamics::Workspace<K>,
    rec: &mut record::Recorder<K>,
    q: &[f64],
    v: &[f64],
) -> Result<bool, Error> {
    match rec.push(system, ws, 0.0, q, v) {
        Ok(()) => Ok(true),
        Err(record::SampleError::Singular) => Ok(false),
        Err(record::SampleError::NonFinite { channel, value }) => {
            Err(initial_overflow(system, &channel, value))
        }
    }
}

/// A body whose weight overflows the floating-point range (a mass near 1.8e308 kg) is an
/// error before the run, naming the body.
fn check_weights<K: Kind>(system: &System<K>) -> Result<(), Error> {
    let g = K::norm(&system.gravity);
    match system.bodies.iter().find(|b| !(b.mass * g).is_finite()) {
        Some(b) => Err(crate::error::Named::body(&b.name).error(
            "mass",
            format!(
                "mass = {:e} kg: its weight m |g| = {} N overflows the floating-point range \
                 (about 1.8e308); check the value and its unit",
                b.mass,
                b.mass * g
            ),
        )),
        None => Ok(()),
    }
}

/// The error of a model whose initial state (t = 0) gives a non-finite output: it names
/// the channel's element, so that the message is located in the model.
fn initial_overflow<K: Kind>(system: &System<K>, channel: &str, value: f64) -> Error {
    let (element, quantity) = channel.rsplit_once('.').unwrap_or(("model", channel));
    let kind = if system.bodies.iter().any(|b| b.name == element) {
        "body"
    } else if system.joints.iter().any(|j| j.name == element) {
        "joint"
    } else if system.drivers.iter().any(|d| d.name == element) {
        "driver"
    } else {
        "model"
    };
    let problem = format!(
        "{quantity} = {value} at the initial state (t = 0), before the run: {}",
        record::NON_FINITE_CAUSE
    );
    // A channel is no key of the model file: the error names the element alone.
    match kind {
        "model" => Error::Model(format!("{kind} '{element}': {problem}")),
        _ => crate::error::ElementError::model(kind, element, None, problem),
    }
}

/// The channels a run of `model` with `opts` records (`opts.channels` selects them), in
/// the order of its result, without assembling or running it: what the output's size is
/// estimated from before a run.
pub fn recorded_channels(model: &Model, opts: &SimOptions) -> Result<Vec<String>, Error> {
    recorded_channels_of(&System::new(model)?, opts)
}

/// [`recorded_channels`] of a model already compiled.
pub fn recorded_channels_of<K: Kind>(system: &System<K>, opts: &SimOptions) -> Result<Vec<String>, Error> {
    let ws = dynamics::Workspace::new(system, Vec::new());
    Ok(record::Recorder::new(system, &ws, opts.channels.as_deref(), opts.decimate, opts.energy)?.names())
}

/// Simulates many models with the same options on a pool of `threads` threads (all
/// cores when `None`), in order: result `k` belongs to `models[k]` and is bit for bit the
/// one `simulate` gives, so a batch is a serial loop done faster. One model's error or
/// failure leaves the others untouched. Once `control` is stopped (Ctrl-C), the runs
/// going end as interrupted with what they computed and the models not started are
/// `None`.
///
/// Each thread takes the next model as it finishes one (rayon's `par_bridge`), because
/// runs differ in length (a larger clearance, more impacts): halving the list between
/// threads, as a `par_iter` does first, left one thread with the long runs, and eight
/// founding-case variants ran 1.6-1.8x faster on 2 threads instead of about 1.95x.
pub fn simulate_batch(
    models: &[Model],
    opts: &SimOptions,
    threads: Option<usize>,
    control: &BatchControl,
) -> Vec<Option<Result<SimResult, Error>>> {
    simulate_batch_of(models, |m| prepare(m).map(any::AnyPrepared::Planar), opts, threads, control)
}

/// [`simulate_batch`] of `cases` that `prepare` turns into prepared models, each once, in
/// the batch's threads as its run starts: a front end that holds some models prepared
/// already hands them over instead of compiling them again. As in [`simulate_with`], a
/// run's wall time counts its preparation.
pub fn simulate_batch_of<C: Sync, P: std::borrow::Borrow<any::AnyPrepared>>(
    cases: &[C],
    prepare: impl Fn(&C) -> Result<P, Error> + Sync,
    opts: &SimOptions,
    threads: Option<usize>,
    control: &BatchControl,
) -> Vec<Option<Result<SimResult, Error>>> {
    use rayon::prelude::*;
    let simulate_one = |c: &C| {
        opts.check()?;
        let started = std::time::Instant::now();
        prepare(c)?.borrow().run(opts, &mut &*control, started)
    };
    let one = |c: &C| (!control.stopped()).then(|| control.case(|| simulate_one(c)));
    let run = || {
        let mut done: Vec<(usize, Option<Result<SimResult, Error>>)> =
            cases.iter().enumerate().par_bridge().map(|(k, c)| (k, one(c))).collect();
        done.sort_unstable_by_key(|(k, _)| *k);
        done.into_iter().map(|(_, result)| result).collect()
    };
    match threads {
        Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n.max(1)).build() {
            Ok(pool) => pool.install(run),
            Err(_) => cases.iter().map(one).collect(),
        },
        None => run(),
    }
}

/// Simulates a model from t = 0 to `opts.t_end`. Errors in the model or options come
/// back as `Err`; a run that fails midway returns what it computed, with `Status::Failed`.
pub fn simulate(model: &Model, opts: &SimOptions) -> Result<SimResult, Error> {
    simulate_with(model, opts, &mut Silent)
}

/// [`simulate`] reporting to `monitor`: progress while it runs and, when the monitor
/// takes chunks, the samples as they fill (the result then holds none of them).
pub fn simulate_with(
    model: &Model,
    opts: &SimOptions,
    monitor: &mut dyn Monitor,
) -> Result<SimResult, Error> {
    opts.check()?;
    let started = std::time::Instant::now();
    run_prepared(&prepare(model)?, opts, monitor, started)
}

/// [`simulate_with`] of a spatial model.
pub fn simulate_spatial(
    model: &SpatialModel,
    opts: &SimOptions,
    monitor: &mut dyn Monitor,
) -> Result<SimResult, Error> {
    opts.check()?;
    let started = std::time::Instant::now();
    run_prepared(&prepare_model::<Spatial>(model)?, opts, monitor, started)
}

/// [`check`] of a spatial model.
pub fn check_spatial(model: &SpatialModel) -> Result<Vec<String>, Error> {
    check_prepared(&prepare_model::<Spatial>(model)?)
}

/// [`simulate_with`] of a model already prepared, which a front end that checked it
/// first ([`check_prepared`]) runs without compiling it again; the result is bit for bit
/// the same.
pub fn simulate_prepared<K: Kind>(
    prepared: &Prepared<K>,
    opts: &SimOptions,
    monitor: &mut dyn Monitor,
) -> Result<SimResult, Error> {
    opts.check()?;
    run_prepared(prepared, opts, monitor, std::time::Instant::now())
}

/// One run of a prepared model; `started` is when the run's wall time starts.
pub(crate) fn run_prepared<K: Kind>(
    Prepared { system, initial }: &Prepared<K>,
    opts: &SimOptions,
    monitor: &mut dyn Monitor,
    started: std::time::Instant,
) -> Result<SimResult, Error> {
    let mut ode = equations::Ode::new(system, initial.active.clone(), opts.rtol, opts.atol);
    let mut rec =
        record::Recorder::new(system, &ode.ws, opts.channels.as_deref(), opts.decimate, opts.energy)?;
    ode.ws.profile = opts.profile.then(Profile::default);
    let interpreted = if opts.compiled || opts.exact_jacobian {
        ode.ws.compile(opts.compiled, opts.exact_jacobian).err()
    } else {
        Some(crate::dynamics::compiled::TURNED_OFF.to_string())
    };
    let n = system.layout.nq();
    let mut y = [initial.q.as_slice(), initial.v.as_slice()].concat();
    let mut stats = RunStats::default();
    let mut log = events::ImpactLog::new(system);
    if opts.every_step && opts.rate.is_some() {
        rec.mark_samples();
    }
    let mut wear = opts.wear.as_ref().map(|w| wear::Wear::new(system, w)).transpose()?;
    if let Some(wear) = wear.as_mut() {
        wear.start(system, &ode.ws.contacts, &y[..n], &y[n..]);
    }
    let mut status = if record_initial(system, &mut ode.ws, &mut rec, &y[..n], &y[n..])? {
        rec.mark_sample();
        integrate::integrate(&mut ode, opts, &mut y, &mut rec, &mut log, &mut stats, monitor, wear.as_mut())
    } else {
        Status::Failed { time: 0.0, reason: SINGULAR_AT_START.into() }
    };
    if status == Status::Finished {
        match rec.push_end(system, &mut ode.ws, opts.t_end, &y[..n], &y[n..]) {
            Ok(()) => {}
            Err(record::SampleError::Singular) => {
                status = Status::Failed {
                    time: opts.t_end,
                    reason: "the constraint equations became singular at the end time".into(),
                };
            }
            Err(record::SampleError::NonFinite { channel, value }) => {
                status = Status::Failed {
                    time: opts.t_end,
                    reason: format!("{channel} = {value}: {}", record::NON_FINITE_CAUSE),
                };
            }
        }
    }
    if monitor.chunk_len().is_some() && !rec.time.is_empty() {
        let last = rec.time[rec.time.len() - 1];
        match monitor.samples(&rec.names(), &rec.time, &rec.data) {
            Ok(()) => rec.clear(),
            Err(stop) if status == Status::Finished => {
                status = stop.status(last, "stopped by the output sink")
            }
            Err(_) => {}
        }
    }
    if stats.method.is_empty() {
        stats.method = opts.method.name().to_string();
    }
    stats.rhs_evaluations = ode.evaluations;
    stats.profile = ode.ws.profile.take();
    (stats.compiled, stats.compile_time) = match (&ode.ws.compiled, interpreted) {
        (Some(stage), _) => (stage.summary(), stage.compile_seconds),
        (None, why) => (format!("interpreted: {}", why.unwrap_or_default()), 0.0),
    };
    stats.wall_time = started.elapsed().as_secs_f64();
    let impacts = log.joint_impacts(system);
    let clearances = system.clearances.iter().map(ClearanceJoint::data).collect();
    Ok(SimResult {
        names: rec.names(),
        samples: rec.samples,
        peaks: rec.peaks,
        time: rec.time,
        data: rec.data,
        stats,
        status,
        warnings: system.warnings.clone(),
        impacts,
        clearances,
        wear: wear.map(wear::Wear::finish).unwrap_or_default(),
    })
}
