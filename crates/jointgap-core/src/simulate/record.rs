//! Output channels: which quantities exist (DESIGN.md naming) and how each sample is
//! computed from a state by one full evaluation of the equations of motion.

use super::energy::{Accounts, Amounts, ACCOUNTS};
use crate::dynamics::{accelerations, Singular, Workspace};
use crate::error::Error;
use crate::integrators::ode::DenseStep;
use crate::mechanics::contact::{ClearanceJoint, ContactState};
use crate::mechanics::kind::ForceLaw;
use crate::mechanics::planar::Planar;
use crate::system::System;

use super::Kind;

/// Why a sample was not recorded.
#[derive(Debug, Clone, PartialEq)]
pub enum SampleError {
    /// The constraint equations are singular at the sample's state.
    Singular,
    /// A kept channel came out infinite or NaN (the first one in model order).
    NonFinite {
        /// Its name, `<element>.<quantity>`.
        channel: String,
        /// Its value: `inf`, `-inf` or `NaN`.
        value: f64,
    },
}

/// Why a run can produce an infinite or undefined number, and what to check: the tail of
/// the message of a run stopped by one.
pub const NON_FINITE_CAUSE: &str = "a number overflowed the floating-point range (about 1.8e308) or \
     was undefined (0/0, inf - inf); check the magnitudes and units of the masses, inertias, \
     stiffnesses, loads and speeds";

impl From<Singular> for SampleError {
    fn from(_: Singular) -> Self {
        SampleError::Singular
    }
}

/// The system's channels, before the energy accounts.
const SYSTEM_QUANTITIES: [&str; 3] = ["kinetic_energy", "potential_energy", "constraint_error"];

/// Collects the chosen channels at sample times.
pub struct Recorder<K: Kind = Planar> {
    /// All channel names of the system, in model order.
    all: Vec<String>,
    /// Indices into `all` that are kept.
    keep: Vec<usize>,
    /// Whether each of `all` is kept.
    kept: Vec<bool>,
    /// Active index of each row (`None`: redundant row).
    active_of_row: Vec<Option<usize>>,
    /// Sample times.
    pub time: Vec<f64>,
    /// One vector per kept channel.
    pub data: Vec<Vec<f64>>,
    /// Time of the latest record asked for, kept or decimated away.
    pub last_time: Option<f64>,
    /// Largest absolute value of each kept channel over every evaluated record: the kept
    /// ones and those only looked at ([`Recorder::peek`]); NaN is passed over.
    pub peaks: Vec<f64>,
    /// Keep every `decimate`-th record.
    decimate: usize,
    /// Records asked for so far.
    count: usize,
    /// Records kept so far, including those already handed on in chunks.
    kept_count: usize,
    /// Time of the latest kept record.
    last_kept: Option<f64>,
    /// Whether the latest record asked for was kept.
    latest_kept: bool,
    /// Indices (among the kept records, from 0) of the output samples at the rate and at
    /// the end time, when the run records every step as well (`None` otherwise: then every
    /// record is an output sample, or, without a rate, a step). Marked where they are
    /// recorded, so that nobody has to recognise them by their time.
    pub samples: Option<Vec<usize>>,
    values: Vec<f64>,
    /// The energy accounts, when the run keeps them.
    accounts: Option<Accounts<K>>,
}

/// Every channel name of a system, in model order; the energy accounts' with `energy`.
pub fn channel_names<K: Kind>(sys: &System<K>, energy: bool) -> Vec<String> {
    let mut names = Vec::new();
    for b in &sys.bodies {
        names.extend(K::CHANNELS.iter().chain(K::BODY_EXTRA).map(|q| format!("{}.{q}", b.name)));
    }
    for j in &sys.joints {
        names.extend(K::joint_force_channels(sys, j).into_iter().map(|(q, point)| match point {
            None => format!("{}.{q}", j.name),
            Some(i) => format!("{}.p{i}.{q}", j.name),
        }));
        names.extend(K::coordinate_quantities(j.kind).iter().map(|q| format!("{}.{q}", j.name)));
    }
    for d in &sys.drivers {
        names.push(format!("{}.{}", d.name, if d.rotation { "torque" } else { "force" }));
    }
    for m in &sys.markers {
        names.extend(K::MARKER_QUANTITIES.iter().map(|q| format!("{}.{q}", m.name)));
    }
    for q in SYSTEM_QUANTITIES {
        names.push(format!("system.{q}"));
    }
    if energy {
        for q in ACCOUNTS.iter().chain(&["energy_balance"]) {
            names.push(format!("system.{q}"));
        }
    }
    names
}

/// The name of entry `i` of the state `y = (q, v)` as the channel that records it,
/// e.g. `crank.omega`.
pub fn state_name<K: Kind>(sys: &System<K>, i: usize) -> String {
    let nq = sys.layout.nq();
    let slots = sys.layout.slots();
    let (k, quantity) = if i < nq {
        let k = slots.iter().position(|s| s.q().contains(&i)).expect("a position of a body");
        (k, i - slots[k].q_at)
    } else {
        let k = slots.iter().position(|s| s.v().contains(&(i - nq))).expect("a velocity of a body");
        (k, slots[k].shape.nq + i - nq - slots[k].v_at)
    };
    format!("{}.{}", sys.bodies[k].name, K::CHANNELS[quantity])
}

impl<K: Kind> Recorder<K> {
    /// Selects channels by exact name or `element.*`; unknown selections are an error.
    /// Output samples are marked (see [`Recorder::mark_sample`]) once
    /// [`Recorder::mark_samples`] is called.
    /// With `energy` the energy accounts are kept, from the run's workspace `ws`.
    pub fn new(
        sys: &System<K>,
        ws: &Workspace<K>,
        select: Option<&[String]>,
        decimate: usize,
        energy: bool,
    ) -> Result<Self, Error> {
        let all = channel_names(sys, energy);
        let keep: Vec<usize> = match select {
            None => (0..all.len()).collect(),
            Some(patterns) => {
                for p in patterns {
                    let hit = match p.strip_suffix(".*") {
                        Some(prefix) => all.iter().any(|n| n.split('.').next() == Some(prefix)),
                        None => all.contains(p),
                    };
                    if !hit {
                        let account = p
                            .strip_prefix("system.")
                            .is_some_and(|q| ACCOUNTS.contains(&q) || q == "energy_balance");
                        let hint = if account && !energy {
                            " (the energy accounts are kept when the run asks for them: option energy)"
                        } else {
                            ""
                        };
                        return Err(Error::Options {
                            key: "channels",
                            problem: format!("channel '{p}' is not an output of this model{hint}"),
                        });
                    }
                }
                (0..all.len())
                    .filter(|&k| {
                        patterns.iter().any(|p| match p.strip_suffix(".*") {
                            Some(prefix) => all[k].split('.').next() == Some(prefix),
                            None => &all[k] == p,
                        })
                    })
                    .collect()
            }
        };
        let mut active_of_row = vec![None; sys.rows.len()];
        for (a, &r) in ws.active.iter().enumerate() {
            active_of_row[r] = Some(a);
        }
        let mut kept = vec![false; all.len()];
        keep.iter().for_each(|&k| kept[k] = true);
        Ok(Recorder {
            accounts: energy.then(|| Accounts::new(sys, ws)),
            kept,
            data: vec![Vec::new(); keep.len()],
            peaks: vec![0.0; keep.len()],
            values: vec![0.0; all.len()],
            all,
            keep,
            active_of_row,
            time: Vec::new(),
            last_time: None,
            decimate: decimate.max(1),
            count: 0,
            kept_count: 0,
            last_kept: None,
            latest_kept: false,
            samples: None,
        })
    }

    /// Marks output samples from now on: for a run whose records mix the samples at the
    /// rate with every accepted step.
    pub fn mark_samples(&mut self) {
        self.samples.get_or_insert_with(Vec::new);
    }

    /// Marks the latest record as an output sample, if it was kept and samples are marked.
    pub fn mark_sample(&mut self) {
        if let (true, Some(marks)) = (self.latest_kept, self.samples.as_mut()) {
            let index = self.kept_count - 1;
            if marks.last() != Some(&index) {
                marks.push(index);
            }
        }
    }

    /// Records the state at the end time `t` as an output sample, whatever the decimation,
    /// unless the latest kept record is already there: a run keeps its end state when
    /// `t_end` is off the output grid or decimation would drop it.
    pub fn push_end(
        &mut self,
        sys: &System<K>,
        ws: &mut Workspace<K>,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), SampleError> {
        if self.last_kept.is_some_and(|tl| tl >= t) {
            self.latest_kept = true;
        } else {
            self.record(sys, ws, t, q, v, Keep::Always)?;
        }
        self.mark_sample();
        Ok(())
    }

    /// Empties the sample buffers (after a chunk was handed on), keeping their capacity.
    pub fn clear(&mut self) {
        self.time.clear();
        self.data.iter_mut().for_each(Vec::clear);
    }

    /// Names of the kept channels.
    pub fn names(&self) -> Vec<String> {
        self.keep.iter().map(|&k| self.all[k].clone()).collect()
    }

    /// Takes an accepted step into the energy accounts (when kept): the step `step` from
    /// `t0`, ended at `t1`, with the clearance joints in `contacts` throughout. Called
    /// before the step's samples.
    pub fn begin_step(
        &mut self,
        sys: &System<K>,
        contacts: &[ContactState],
        step: &DenseStep,
        t0: f64,
        t1: f64,
    ) -> Result<(), Singular> {
        match self.accounts.as_mut() {
            Some(accounts) => accounts.begin_step(sys, contacts, step, t0, t1),
            None => Ok(()),
        }
    }

    /// Records one sample at `(t, q, v)`, unless decimation drops it. A sample with a
    /// non-finite kept channel is not recorded: the error names that channel.
    pub fn push(
        &mut self,
        sys: &System<K>,
        ws: &mut Workspace<K>,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), SampleError> {
        self.record(sys, ws, t, q, v, Keep::Decimated)
    }

    /// Evaluates the channels at `(t, q, v)` for their peaks only, keeping no record: the
    /// peaks over every accepted step of a run that keeps only its samples.
    pub fn peek(
        &mut self,
        sys: &System<K>,
        ws: &mut Workspace<K>,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), SampleError> {
        self.record(sys, ws, t, q, v, Keep::Peek)
    }

    /// [`Recorder::push`], [`Recorder::push_end`] and [`Recorder::peek`].
    fn record(
        &mut self,
        sys: &System<K>,
        ws: &mut Workspace<K>,
        t: f64,
        q: &[f64],
        v: &[f64],
        how: Keep,
    ) -> Result<(), SampleError> {
        if how != Keep::Peek {
            let keep = how == Keep::Always || self.count.is_multiple_of(self.decimate);
            self.count += 1;
            self.last_time = Some(t);
            self.latest_kept = keep;
            if !keep {
                return Ok(());
            }
        }
        let accounts = match self.accounts.as_mut() {
            Some(accounts) if self.kept[self.kept.len() - ACCOUNTS.len() - 1..].iter().any(|&k| k) => {
                Some(accounts.at(sys, t)?)
            }
            _ => None,
        };
        ws.t_piece = t;
        accelerations(sys, t, q, v, ws)?;
        let mut out = Cursor { values: &mut self.values, kept: &self.kept, next: 0 };
        if K::IDENTITY_RATE && K::BODY_EXTRA.is_empty() {
            let mut put = |x: f64| out.put(x);
            for slot in sys.layout.slots() {
                q[slot.q()].iter().chain(&v[slot.v()]).chain(&ws.qdd[slot.v()]).for_each(|&x| put(x));
            }
        } else {
            for (b, slot) in sys.bodies.iter().zip(sys.layout.slots()) {
                // A sample between step ends comes from the dense output, which keeps a
                // quaternion unit only to the step's error: the body's orientation is the
                // normalised one (what every evaluation reads), and that is recorded.
                let mut positions = q[slot.q()].to_vec();
                K::normalise(&mut positions);
                positions.iter().chain(&v[slot.v()]).chain(&ws.qdd[slot.v()]).for_each(|&x| out.put(x));
                if !out.skipped(K::BODY_EXTRA.len()) {
                    K::put_body_extra(&mut out, b, &positions, &v[slot.v()], &ws.qdd[slot.v()]);
                }
            }
        }
        // Reactions: generalised constraint force on body j is -Cq_j^T lambda.
        let lambda_of = |r: usize| self.active_of_row[r].map_or(0.0, |a| ws.lambda[a]);
        for j in &sys.joints {
            let (bi, bj) = (sys.body_state(j.body_i, q, v), sys.body_state(j.body_j, q, v));
            if !out.skipped(K::joint_force_channel_count(sys, j)) {
                K::put_joint_forces(&mut out, sys, ws, j, (&bi, &bj), (q, v), &lambda_of);
            }
            let coordinates = K::coordinate_quantities(j.kind).len();
            if coordinates > 0 && !out.skipped(coordinates) {
                K::put_joint_coordinates(&mut out, j, &bi, &bj);
            }
        }
        for d in &sys.drivers {
            if out.skipped(1) {
                continue;
            }
            let row = &sys.rows[d.row];
            let bi = sys.body_state(row.body_i, q, v);
            let bj = sys.body_state(row.body_j, q, v);
            let ev = K::eval(&row.kind, &bi, &bj, d.profile.motion(t));
            out.put(K::driver_effort(&ev, d.rotation, row.body_j.is_some(), lambda_of(d.row)));
        }
        for m in &sys.markers {
            if !out.skipped(K::MARKER_QUANTITIES.len()) {
                K::put_marker(&mut out, sys, ws, m, q, v);
            }
        }
        // The system's channels close the list; the energy accounts' with them.
        if !out.skipped(out.values.len() - out.next) {
            out.put_system(sys, ws, q, v, self.accounts.is_some().then_some(accounts));
        }
        debug_assert_eq!(out.next, out.values.len(), "channels written and named differ");
        // One sum per sample is the whole cost of the check: a single inf or NaN makes it
        // non-finite (finite values that overflow the sum are searched for in vain and pass).
        if !self.keep.iter().map(|&k| self.values[k]).sum::<f64>().is_finite() {
            if let Some(&k) = self.keep.iter().find(|&&k| !self.values[k].is_finite()) {
                return Err(SampleError::NonFinite { channel: self.all[k].clone(), value: self.values[k] });
            }
        }
        for (peak, &k) in self.peaks.iter_mut().zip(&self.keep) {
            *peak = peak.max(self.values[k].abs());
        }
        if how == Keep::Peek {
            return Ok(());
        }
        self.time.push(t);
        self.kept_count += 1;
        self.last_kept = Some(t);
        for (slot, &k) in self.keep.iter().enumerate() {
            self.data[slot].push(self.values[k]);
        }
        Ok(())
    }
}

/// Which records a call keeps.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Keep {
    /// Every `decimate`-th.
    Decimated,
    /// This one, whatever the decimation.
    Always,
    /// None: the channels are evaluated for their peaks only.
    Peek,
}

/// Writes one sample's channels in order, and skips the groups of channels none of
/// which is kept, so that a run that records a few channels does not compute the rest.
pub struct Cursor<'a> {
    values: &'a mut [f64],
    kept: &'a [bool],
    next: usize,
}

impl Cursor<'_> {
    /// Writes the next channel.
    pub fn put(&mut self, x: f64) {
        self.values[self.next] = x;
        self.next += 1;
    }

    /// Passes over the next `len` channels if none of them is kept.
    fn skipped(&mut self, len: usize) -> bool {
        let skip = !self.kept[self.next..self.next + len].iter().any(|&k| k);
        if skip {
            self.next += len;
        }
        skip
    }

    /// The system's channels: kinetic and potential energy, constraint error, and, when
    /// the run keeps them (`Some`), the energy accounts with the balance
    /// `T + V - W_in + D` (passed over when none of them is kept: `Some(None)`).
    fn put_system<K: Kind>(
        &mut self,
        sys: &System<K>,
        ws: &Workspace<K>,
        q: &[f64],
        v: &[f64],
        accounts: Option<Option<Amounts>>,
    ) {
        let mut kinetic = 0.0;
        let mut potential = 0.0;
        for (b, slot) in sys.bodies.iter().zip(sys.layout.slots()) {
            kinetic += K::kinetic_energy(b.mass, &b.inertia, &v[slot.v()]);
            potential -= K::gravity_work(b.mass, &sys.gravity, &q[slot.q()]);
        }
        for f in &sys.forces {
            potential += f.potential_energy(|b| sys.body_state(b, q, v));
        }
        for (k, c) in sys.clearances.iter().enumerate() {
            for p in sys.contact_points(k, q, v).iter() {
                potential += c.elastic_energy(p);
            }
        }
        self.put(kinetic);
        self.put(potential);
        self.put(if ws.active.is_empty() { 0.0 } else { ws.c.amax() });
        match accounts {
            Some(Some([driver, load, damper, contact, friction])) => {
                for x in [driver, load, damper, contact, friction] {
                    self.put(x);
                }
                self.put(kinetic + potential - (driver + load) + (damper + contact + friction));
            }
            Some(None) => self.next += ACCOUNTS.len() + 1,
            None => {}
        }
    }
}
