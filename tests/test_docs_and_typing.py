"""The documentation is self-contained and true to the package: the physics reference
is in the repository and every citation of it names a section it has; its founding-case
data are those of the example file; the lazily loaded names of ``jointgap`` are listed
and typed, so that the tutorials' own Python passes ``mypy --strict``; ``python -m
jointgap`` is the command."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import jointgap
import pytest

ROOT = Path(__file__).resolve().parent.parent
PHYSICS = ROOT / "docs" / "physics.md"
SKIPPED = {"target", ".git", "out", "demo-output", "__pycache__"}


def _citing() -> list[Path]:
    """Every source and documentation file that may cite the reference (build output,
    virtual environments and run output left out)."""
    found = []
    for folder, dirs, names in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in SKIPPED and not d.startswith(".")]
        found += [
            Path(folder) / n
            for n in names
            if n.endswith((".md", ".py", ".rs", ".toml")) or n == "Makefile"
        ]
    return found


CITING = _citing()


def _sections() -> dict[int, str]:
    text = PHYSICS.read_text(encoding="utf-8")
    return {int(n): title for n, title in re.findall(r"^## (\d+)\. (.+)$", text, re.M)}


def test_no_file_cites_a_physics_reference_outside_the_repository() -> None:
    offenders = [
        str(p.relative_to(ROOT))
        for p in CITING
        if p != Path(__file__)
        and re.search(r"PHYSICS\.md|shared/|/work/", p.read_text(encoding="utf-8", errors="ignore"))
    ]
    assert offenders == []


def test_every_cited_section_of_the_physics_reference_exists() -> None:
    sections = _sections()
    assert sorted(sections) == list(range(1, 8))
    cited = 0
    pattern = re.compile(r"physics\.md\)?,? sections? (\d)(?:-(\d)|((?:(?:, | and )\d)+))?")
    for path in CITING:
        for m in pattern.finditer(path.read_text(encoding="utf-8", errors="ignore")):
            numbers = [int(m.group(1))]
            if m.group(2):
                numbers = list(range(numbers[0], int(m.group(2)) + 1))
            numbers += [int(n) for n in re.findall(r"\d", m.group(3) or "")]
            for n in numbers:
                assert n in sections, f"{path}: section {n} of docs/physics.md"
                cited += 1
    assert cited > 30  # README, docs, the calibrate help, tests, crates, benchmarks
    # Section names quoted in the docs are the headings' own.
    for path in (ROOT / "docs").glob("*.md"):
        text = path.read_text(encoding="utf-8")
        for n, name in re.findall(r"physics\.md\)?,? sections? (\d) \"([^\"]+)\"", text):
            assert sections[int(n)].startswith(" ".join(name.split())), (path, n, name)


def test_the_calibrate_help_cites_the_reference(capsys) -> None:
    from jointgap.cli import main

    with pytest.raises(SystemExit):
        main(["calibrate", "--help"])
    assert "docs/physics.md section 3" in capsys.readouterr().out


def test_the_founding_data_match_the_example_file() -> None:
    """The numbers of docs/physics.md section 5 are those the example runs with, and its
    stated K follows from its materials by its own formula (section 3)."""
    text = PHYSICS.read_text(encoding="utf-8")
    founding = text.split("## 5. The founding case")[1].split("## 6.")[0]
    model = tomllib.loads((ROOT / "examples" / "slider_crank_clearance.toml").read_text())
    bodies = {b["name"]: b for b in model["body"]}
    rows = {
        "crank": (0.08, 2.37, 0.01201),
        "connecting rod": (0.32, 0.72, 0.0006926),
    }
    for name, (length, mass, inertia) in rows.items():
        assert f"| {name} | {length:g} | {mass:g} | {inertia:g} |" in founding
    assert "| slider | - | 2.28 | - |" in founding
    assert bodies["crank"]["mass"] == "2.37 kg" and bodies["rod"]["mass"] == "0.72 kg"
    assert bodies["slider"]["mass"] == "2.28 kg"
    assert bodies["crank"]["inertia"] == "0.01201 kg*m^2"
    assert bodies["rod"]["inertia"] == "0.0006926 kg*m^2"
    crank_pin = bodies["crank"]["points"]["A"][0]
    rod_ends = bodies["rod"]["points"]
    assert crank_pin == "0.04 m" and rod_ends["B"][0] == "0.16 m"  # 0.08 m and 0.32 m bars
    joint = next(j for j in model["joint"] if j["name"] == "rod_slider")
    assert joint["bearing_radius"] == "7.5 mm" and joint["clearance"] == "0.5 mm"
    assert joint["normal_law"]["c_max"] == "27960 N*s/m"
    assert joint["normal_law"]["d_max"] == "1e-5 m" and joint["normal_law"]["exponent"] == 1.5
    friction = joint["friction"]
    assert (friction["mu_s"], friction["mu_d"]) == (0.08, 0.05)
    assert (friction["v_s"], friction["v_d"]) == ("0.0001 m/s", "0.01016 m/s")
    for quantity in ("C_max = 27960 N s/m", "d_max = 1e-5 m", "mu_s = 0.08", "mu_d = 0.05"):
        assert quantity in founding
    assert "v_s = 0.0001 m/s, v_d = 0.01016 m/s" in founding
    assert "E = 207 GPa" in founding and "E = 97 GPa" in founding
    driver = model["driver"][0]["profile"]
    assert driver == {"type": "linear_ramp", "speed": "300 rpm", "ramp_time": "0.2 s"}
    # K from section 3's formula, the bearing radius negative.
    sigma = 2 * [(1 - 0.3**2)]
    compliance = sigma[0] / 207e9 + sigma[1] / 97e9
    r_j, r_b = 0.007, -0.0075
    k = 4 / (3 * compliance) * math.sqrt(r_j * r_b / (r_j + r_b))
    assert k == pytest.approx(3.136e10, rel=5e-4)
    assert "K = 3.136e10 N/m^1.5" in founding
    # The V_avg range that Table IV implies: V = 3 K (1 - r^2) d_max^n / (4 C_max).
    table = re.findall(r"^\| \d \| (\d+) \| [\d.]+ \| ([\d.]+) \|$", founding, re.M)
    assert len(table) == 7
    speeds = [3 * k * (1 - float(r) ** 2) * 1e-5**1.5 / (4 * float(c)) for c, r in table]
    assert 0.014 < min(speeds) < 0.0145 and 0.018 < max(speeds) < 0.019


def test_lazy_names_are_listed_and_typed() -> None:
    from jointgap import comparison, measured, study

    lazy = (
        "compare",
        "read_measured",
        "synthetic_record",
        "load_results",
        "load_study",
        "run_study",
    )
    for name in lazy:
        assert name in dir(jointgap) and name in jointgap.__all__
    assert jointgap.compare is comparison.compare
    assert jointgap.read_measured is measured.read_measured
    assert jointgap.synthetic_record is measured.synthetic_record
    assert jointgap.load_results is study.load_results
    assert jointgap.load_study is study.load_study
    assert jointgap.run_study is study.run_study
    assert set(jointgap.__all__) <= set(dir(jointgap))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        _ = jointgap.nothing  # type: ignore[attr-defined]


def _script(path: Path) -> str:
    """A page's Python blocks as one script: the complete ones (those that import
    jointgap) first, then the fragments that go on from them."""
    blocks = re.findall(r"^```python\n(.*?)^```", path.read_text(encoding="utf-8"), re.M | re.S)
    whole = [b for b in blocks if re.search(r"^import jointgap|^from jointgap", b, re.M)]
    return "\n".join(whole + [b for b in blocks if b not in whole])


# The libraries' own types are not under test: skipping them keeps the check quick.
# The package itself is checked strictly by `make lint`; here only the scripts count.
MYPY_CONFIG = """\
[mypy]
strict = True
[mypy-numpy.*,pandas.*,scipy.*,matplotlib.*,pyarrow.*,dask.*,distributed.*]
follow_imports = skip
follow_imports_for_stubs = True
ignore_missing_imports = True
[mypy-jointgap.*]
ignore_errors = True
"""


def test_the_tutorials_python_passes_mypy_strict(tmp_path) -> None:
    """The Python of the tutorials and the README, type-checked as a user's script
    would be: the lazily loaded names must have their real signatures, not ``object``
    (a call of ``object`` is an error)."""
    pytest.importorskip("mypy")
    sources = [ROOT / "README.md", *sorted((ROOT / "docs").glob("tutorial-*.md"))]
    files = []
    for source in sources:
        script = _script(source)
        if script:
            path = tmp_path / f"{source.stem.replace('-', '_')}.py"
            path.write_text(script, encoding="utf-8")
            files.append(str(path))
    assert len(files) == 3
    (tmp_path / "mypy.ini").write_text(MYPY_CONFIG, encoding="utf-8")
    mypy = [sys.executable, "-m", "mypy", "--config-file", str(tmp_path / "mypy.ini")]
    done = subprocess.run(
        [*mypy, "--no-incremental", "--cache-dir", str(tmp_path / ".mypy_cache"), *files],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Success: no issues found in 3 source files" in done.stdout


def test_python_dash_m_jointgap_is_the_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "jointgap", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0 and done.stdout.strip() == f"jointgap {jointgap.__version__}"
    done = subprocess.run([sys.executable, "-m", "jointgap"], capture_output=True, text=True)
    assert done.returncode == 2 and "usage: jointgap" in done.stderr


def test_synthesize_help_names_the_options_it_describes(capsys) -> None:
    """The help of synthesize says which option is the record's rate (--sample-rate) and
    which the run's (--rate), with the parser's own defaults."""
    from jointgap.cli import build_parser, main

    with pytest.raises(SystemExit):
        main(["synthesize", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "sampled at --rate (default 50 kHz" in text
    assert "sample --signal at --sample-rate (default 5 kHz)" in text
    assert "(--lag, default 0.01 s;" in text
    given = ["synthesize", "m.toml", "--signal", "x", "--out", "o", "--t-end", "1"]
    args = build_parser().parse_args(given)
    assert (args.rate, args.sample_rate, args.lag) == ("50000", "5000", "0.01")


def test_the_measured_tutorial_states_the_reader_and_folders_as_they_are(tmp_path, engine) -> None:
    import inspect

    from jointgap.cli import main

    text = " ".join((ROOT / "docs" / "tutorial-measured-data.md").read_text().split())
    stated = re.search(r"`jointgap\.read_measured\((.*?)\)`", text)
    assert stated is not None
    signature = inspect.signature(jointgap.read_measured).parameters.values()
    real = []
    for p in signature:
        if p.kind == p.KEYWORD_ONLY and "*" not in real:
            real.append("*")
        real.append(p.name if p.default is p.empty else f"{p.name}={p.default!r}")
    assert [p.strip() for p in stated.group(1).split(",")] == [r.replace("'", '"') for r in real]
    # "Every option that writes a file creates its folder": synthesize --out here.
    record = tmp_path / "new" / "folder" / "m.csv"
    args = ["synthesize", "examples/slider_crank_ideal.toml", "--signal", "slider.ax"]
    assert main([*args, "--t-end", "0.05", "--out", str(record), "--rate", "10000"]) == 0
    assert jointgap.read_measured(record, "slider.ax").unit == "m/s^2"
