"""The core's stages import only the stages before them (docs/architecture.md).

model data -> mechanics -> system -> dynamics -> integrators -> simulate, with the plain
vocabulary (errors, the model's defaults, math, the number type the kernels are written
over and the compiler of its recordings, profile, output types) below all of them; the
integrators know nothing of mechanics. A `crate::<module>` path in a file of one stage
naming a later stage (or, for the integrators, any stage of mechanics) fails here,
before it turns into an import circle.
"""

from __future__ import annotations

import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "crates" / "jointgap-core" / "src"

#: What each stage may use besides the vocabulary and itself.
VOCABULARY = {"error", "defaults", "math", "scalar", "codegen", "profile", "output", "model"}
ALLOWED = {
    "model": {"defaults", "error"},
    "mechanics": VOCABULARY,
    "system": VOCABULARY | {"mechanics"},
    "dynamics": VOCABULARY | {"mechanics", "system"},
    "integrators": {"error", "math", "profile"},
    "simulate": VOCABULARY | {"mechanics", "system", "dynamics", "integrators"},
}
_PATH = re.compile(r"\bcrate::([a-z_]+)")


def _stage(path: Path) -> str:
    part = path.relative_to(SRC).parts[0]
    return part.removesuffix(".rs")


def test_each_stage_imports_only_the_stages_before_it() -> None:
    wrong: list[str] = []
    stages = set()
    for path in sorted(SRC.rglob("*.rs")):
        stage = _stage(path)
        if stage not in ALLOWED:
            continue  # lib.rs and the vocabulary
        stages.add(stage)
        code = "\n".join(line.split("//")[0] for line in path.read_text().splitlines())
        for used in sorted(set(_PATH.findall(code)) - {stage}):
            if used not in ALLOWED[stage]:
                wrong.append(f"{path.relative_to(SRC)} uses crate::{used}")
    assert stages == set(ALLOWED), "a stage's folder is missing: update this test and the docs"
    assert wrong == []


def test_the_vocabulary_imports_no_stage() -> None:
    stages = set(ALLOWED) - {"model"}
    files = [SRC / f"{n}.rs" for n in ("error", "defaults", "math", "codegen", "profile", "output")]
    for path in [*files, *sorted((SRC / "scalar").glob("*.rs"))]:
        code = "\n".join(line.split("//")[0] for line in path.read_text().splitlines())
        assert not set(_PATH.findall(code)) & stages, path.name
