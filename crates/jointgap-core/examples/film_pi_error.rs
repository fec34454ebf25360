//! How far the pi-film forms of the journal-bearing film are from the exact
//! positive-pressure (Gumbel) forms: prints the tables of docs/lubrication.md.
//!
//! `cargo run --release -p jointgap-core --example film_pi_error`

use jointgap_core::mechanics::contact::film::{Film, FilmMotion};
use jointgap_core::model::FilmModel;

/// Force along and across the eccentricity for a motion given as eccentricity ratio,
/// its rate [1/s] and the wedge speed [rad/s] (journal speed, bearing and attitude at
/// rest), in units of `mu R L^3 / c^2` (short) or `mu R^3 L / c^2` (long) per 1/s.
fn force(model: FilmModel, eps: f64, eps_rate: f64, wedge: f64) -> (f64, f64) {
    let (r, c, l, mu) = (0.01, 5e-5, 0.01, 0.04);
    let film = Film { radius: r, clearance: c, length: l, viscosity: mu, model };
    let f = film.force(&FilmMotion {
        eccentricity: eps * c,
        eccentricity_rate: eps_rate * c,
        attitude_rate: 0.0,
        omega_journal: wedge,
        omega_bearing: 0.0,
    });
    let unit = match model {
        FilmModel::Short | FilmModel::ShortPi => mu * r * l.powi(3) / (c * c),
        FilmModel::Long | FilmModel::LongPi => mu * r.powi(3) * l / (c * c),
    } * (eps_rate.abs() + wedge.abs());
    (f.along / unit, f.across / unit)
}

fn main() {
    let eps_list = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95];
    for (name, exact, pi) in
        [("short", FilmModel::Short, FilmModel::ShortPi), ("long", FilmModel::Long, FilmModel::LongPi)]
    {
        println!("\nPure squeeze, {name} bearing (force per unit squeeze rate)\n");
        println!("| eps | exact along (approach) | pi along | pi / exact | pi across | exact along (recede) | pi along (recede) |");
        println!("|---|---|---|---|---|---|---|");
        for eps in eps_list {
            let (e_in, _) = force(exact, eps, 1.0, 0.0);
            let (p_in, p_in_t) = force(pi, eps, 1.0, 0.0);
            let (e_out, _) = force(exact, eps, -1.0, 0.0);
            let (p_out, _) = force(pi, eps, -1.0, 0.0);
            println!(
                "| {eps} | {e_in:.4} | {p_in:.4} | {:.3} | {p_in_t:.4} | {e_out:.4} | {p_out:.4} |",
                p_in / e_in
            );
        }
        println!("\nPure wedge, {name} bearing (force per unit wedge speed)\n");
        println!("| eps | exact along | exact across | pi along (wbar > 0) | pi along (wbar < 0) | pi across (wbar < 0) |");
        println!("|---|---|---|---|---|---|");
        for eps in eps_list {
            let (ea, et) = force(exact, eps, 0.0, 1.0);
            let (pa, _) = force(pi, eps, 0.0, 1.0);
            let (na, nt) = force(pi, eps, 0.0, -1.0);
            println!("| {eps} | {ea:.4} | {et:.4} | {pa:.4} | {na:.4} | {nt:.4} |");
        }
    }
}
