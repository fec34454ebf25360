"""The founding slider-crank with its rod-slider joint dry (examples/slider_crank_clearance.toml)
and lubricated (examples/slider_crank_lubricated.toml, the same model but for the joint's
`type` line and its oil film): the slider's acceleration, the journal's orbit in its
bearing, the joint's force and, for the lubricated joint, the film's eccentricity ratio,
drawn side by side in <folder>/dry_vs_lubricated.png (docs/lubrication.md).

    python examples/dry_vs_lubricated.py [folder] [t_end]
"""

from __future__ import annotations

import sys
from pathlib import Path

import jointgap
import matplotlib.pyplot as plt
import numpy as np

HERE = Path(__file__).resolve().parent
JOINT = "rod_slider"


def main(folder: str = "dry_vs_lubricated", t_end: str = "0.5") -> Path:
    runs = {
        "dry": jointgap.load(HERE / "slider_crank_clearance.toml").simulate(
            float(t_end), rate=10_000
        ),
        "lubricated": jointgap.load(HERE / "slider_crank_lubricated.toml").simulate(
            float(t_end), rate=10_000
        ),
    }
    clearance_mm = 1e3 * runs["dry"].clearances[JOINT]["clearance"]
    plt.switch_backend("Agg")
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), layout="constrained")
    colours = {"dry": "tab:red", "lubricated": "tab:blue"}
    for name, r in runs.items():
        t = r.time
        axes[0, 0].plot(t, r["slider.ax"], lw=0.7, color=colours[name], label=name)
        force = np.hypot(r[f"{JOINT}.fx"], r[f"{JOINT}.fy"])
        axes[1, 0].plot(t, force, lw=0.7, color=colours[name], label=name)
        axes[0, 1].plot(
            1e3 * r[f"{JOINT}.ex"], 1e3 * r[f"{JOINT}.ey"], lw=0.5, color=colours[name], label=name
        )
        ax = r["slider.ax"]
        print(
            f"{name:>10}: slider acceleration {ax.min():9.1f} .. {ax.max():7.1f} m/s^2,"
            f" joint force peak {force.max():8.1f} N, {len(r.impacts.get(JOINT, []))} impacts"
        )
    lub = runs["lubricated"]
    axes[1, 1].plot(
        lub.time, lub[f"{JOINT}.eccentricity_ratio"], lw=0.8, color=colours["lubricated"]
    )
    axes[1, 1].set(
        xlabel="time [s]", ylabel="eccentricity ratio e/c", title="lubricated: film", ylim=(0, 1.05)
    )
    circle = np.linspace(0, 2 * np.pi, 200)
    axes[0, 1].plot(clearance_mm * np.cos(circle), clearance_mm * np.sin(circle), "k--", lw=0.8)
    axes[0, 1].set(
        xlabel="ex [mm]", ylabel="ey [mm]", title="journal centre in the bearing", aspect="equal"
    )
    axes[0, 0].set(xlabel="time [s]", ylabel="slider acceleration [m/s^2]", title="slider")
    axes[1, 0].set(xlabel="time [s]", ylabel="|force on the journal| [N]", title=f"joint {JOINT}")
    for ax in (axes[0, 0], axes[1, 0], axes[0, 1]):
        ax.legend(loc="upper right")
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "dry_vs_lubricated.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"figure: {path}")
    return path


if __name__ == "__main__":
    main(*sys.argv[1:3])
