//! `Stepper::attempt`'s contract: an accepted attempt evaluates the ODE last at
//! `(t + h, y_new)`, so the drift check after the step reads the constraint rows of that
//! evaluation (`Workspace::violation_here`) instead of evaluating them again.

use crate::common;

use jointgap_core::dynamics::{violation, Workspace};
use jointgap_core::integrators::stepper::Stepper;
use jointgap_core::simulate::equations::{state_shape, Ode};
use jointgap_core::simulate::integrate::stepper;
use jointgap_core::simulate::prepare;
use jointgap_core::Method;

/// Over 30 accepted steps of the clearance slider-crank from rest, each method's drift
/// from its last evaluation equals a fresh evaluation at the step's end, bit for bit.
#[test]
fn accepted_attempt_evaluates_last_at_its_end() {
    let prepared = prepare(&common::slider_crank_clearance()).unwrap();
    let sys = &prepared.system;
    let n = sys.layout.nq() + sys.layout.nv();
    let steppers: Vec<Box<dyn Stepper<Ode>>> = [Method::Dopri5, Method::Radau5, Method::Sdirk4]
        .into_iter()
        .map(|m| stepper(m, state_shape(sys)))
        .collect();
    for mut stepper in steppers {
        let mut ode = Ode::new(sys, prepared.initial.active.clone(), 1e-7, 1e-10);
        let mut fresh = Workspace::new(sys, prepared.initial.active.clone());
        let mut y = [prepared.initial.q.clone(), prepared.initial.v.clone()].concat();
        let (mut t, mut h) = (0.0, 1e-4);
        let mut f = vec![0.0; n];
        let (mut y_new, mut f_new) = (vec![0.0; n], vec![0.0; n]);
        let mut accepted = 0;
        while accepted < 30 {
            ode.ws.t_piece = t + 0.5 * h;
            ode.rhs(t, &y, &mut f).unwrap();
            let tol = ode.tolerances;
            let attempt = stepper.attempt(&mut ode, tol, t, &y, &f, h, &mut y_new, &mut f_new);
            match attempt {
                Ok(a) if a.error <= 1.0 => {
                    let (q, v) = y_new.split_at(sys.layout.nq());
                    let here = ode.ws.violation_here(v);
                    fresh.t_piece = ode.ws.t_piece;
                    let again = violation(sys, t + h, q, v, &mut fresh);
                    assert_eq!(here, again, "{} at t = {t}", stepper.name());
                    assert!(here.0 > 0.0 && here.1 > 0.0, "{}: no drift to compare", stepper.name());
                    (t, accepted) = (t + h, accepted + 1);
                    y.copy_from_slice(&y_new);
                }
                _ => h *= 0.5,
            }
        }
    }
}
