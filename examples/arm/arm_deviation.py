"""The URDF arm (examples/arm/arm.urdf) moved along the trajectory of
examples/arm/arm_clearance.toml, with the elbow's clearance and with every joint ideal: the
tool point's deviation from the ideal path, printed and drawn in
<folder>/tool_deviation.png (docs/urdf.md).

    python examples/arm/arm_deviation.py [folder] [t_end]
"""

from __future__ import annotations

import sys
from pathlib import Path

from jointgap.robot_path import path_deviation, plot_path_deviation

HERE = Path(__file__).resolve().parent


def main(folder: str = "arm_deviation", t_end: str = "1.5 s") -> None:
    result = path_deviation(HERE / "arm.urdf", HERE / "arm_clearance.toml", "tool", t_end)
    peak, at = result.largest
    print(f"largest deviation of the tool point: {1e3 * peak:.3f} mm at {at:.3f} s")
    print(f"deviation at the end ({result.time[-1]:.3f} s): {1e3 * result.deviation[-1]:.3f} mm")
    impacts = result.runs[1].impacts
    print("elbow impacts: " + ", ".join(f"{k} {len(v)}" for k, v in impacts.items()))
    print(f"figure: {plot_path_deviation(result, folder)}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
