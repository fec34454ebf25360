"""Energy accounts: kinetic + potential - work in + dissipated is conserved.

The founding case with a clearance (examples/slider_crank_clearance.toml: ADAMS IMPACT
contact damping and Coulomb friction) over the ramp, 0.2 s with its impacts, and the
ideal driven slider-crank: the balance holds to 1e-8 of the energy scale. The engine's
own tests (crates/jointgap-core/tests/energy.rs) check each account against closed
forms.
"""

from __future__ import annotations

import jointgap
import numpy as np
from jointgap.cli import main
from reference import simulate_ok

ACCOUNTS = (
    "system.driver_work",
    "system.load_work",
    "system.damper_dissipation",
    "system.contact_dissipation",
    "system.friction_dissipation",
)


def drift_and_scale(r: jointgap.Result) -> tuple[float, float]:
    balance = r["system.energy_balance"]
    scale = max(float(np.max(np.abs(r[c]))) for c in (*ACCOUNTS, "system.kinetic_energy"))
    return float(np.max(np.abs(balance - balance[0]))), scale


def test_balance_over_the_founding_clearance_run():
    model = jointgap.load("examples/slider_crank_clearance.toml")
    r = simulate_ok(model, 0.2, rate=10_000, rtol=1e-11, atol=1e-14, energy=True)
    drift, scale = drift_and_scale(r)
    assert drift < 1e-8 * scale, f"balance moves by {drift:.3e} J of {scale:.3f} J"
    assert len(r.impacts["rod_slider"]) > 5
    contact, friction = r["system.contact_dissipation"], r["system.friction_dissipation"]
    assert np.all(np.diff(contact) >= 0) and np.all(np.diff(friction) >= 0)
    assert contact[-1] > 1e-3 and friction[-1] > 1e-3
    # The balance is T + V - W + D, with the potential energy's elastic contact part.
    rebuilt = (
        r["system.kinetic_energy"]
        + r["system.potential_energy"]
        - r["system.driver_work"]
        - r["system.load_work"]
        + r["system.damper_dissipation"]
        + contact
        + friction
    )
    np.testing.assert_allclose(r["system.energy_balance"], rebuilt, rtol=0, atol=1e-12 * scale)
    assert jointgap.channel_unit("system.energy_balance") == "J"


def test_balance_on_the_ideal_driven_run():
    model = jointgap.load("examples/slider_crank_ideal.toml")
    r = simulate_ok(model, 0.5, rate=10_000, rtol=1e-11, atol=1e-14, energy=True)
    drift, scale = drift_and_scale(r)
    assert drift < 1e-8 * scale, f"balance moves by {drift:.3e} J of {scale:.3f} J"
    # The motor's work is what the mechanism holds: up from rest, net of gravity.
    held = r["system.kinetic_energy"] + r["system.potential_energy"]
    np.testing.assert_allclose(r["system.driver_work"], held - held[0], atol=1e-8 * scale)


def test_cli_energy_flag(tmp_path):
    out = tmp_path / "run"
    args = ["run", "examples/slider_crank_clearance.toml", "--t-end", "0.01", "--rate", "1000"]
    assert main([*args, "--energy", "--out", str(out)]) == 0
    result = jointgap.Result.load(out)
    assert "system.energy_balance" in result.channels
    assert result.options["energy"] is True
