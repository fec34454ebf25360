"""Studies on a real Dask cluster: a scheduler and two workers started here as separate
processes on loopback (the ``dask scheduler`` and ``dask worker`` commands of the venv).
The cluster's table equals the local one, and a worker killed in the middle of a study
loses no case."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pandas as pd
import pytest
from jointgap.cli import main
from jointgap.study import load_results, run_study
from study_files import SMALL, grid_study, write_study

DASK = Path(sys.executable).parent / "dask"


def start_worker(
    address: str, name: str, folder: Path, preload: Path | None = None
) -> subprocess.Popen[bytes]:
    """One worker process with one thread and no nanny: killing it kills the worker."""
    command = [str(DASK), "worker", address, "--name", name, "--nthreads", "1", "--no-nanny"]
    command += ["--no-dashboard", "--local-directory", str(folder)]
    if preload is not None:
        command += ["--preload", str(preload)]
    return subprocess.Popen(
        command, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )


def wait_for_workers(address: str, n: int) -> None:
    from distributed import Client

    with Client(address, timeout="60s") as client:
        client.wait_for_workers(n, timeout=60)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory) -> Iterator[tuple[str, Path]]:
    """A scheduler and two workers on 127.0.0.1; yields the address and a scratch folder."""
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    folder = tmp_path_factory.mktemp("dask")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    scheduler = [str(DASK), "scheduler", "--host", "127.0.0.1", "--port", str(port)]
    processes = [
        subprocess.Popen(
            [*scheduler, "--no-dashboard"],
            cwd=folder,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        processes += [start_worker(address, f"worker-{k}", folder) for k in (1, 2)]
        wait_for_workers(address, 2)
        yield address, folder
    finally:  # a test cluster: no graceful shutdown to wait for
        for process in processes:
            process.kill()
            process.wait(timeout=20)


def test_cluster_table_equals_the_local_table(cluster, tmp_path, capsys) -> None:
    address, _ = cluster
    path = write_study(tmp_path, SMALL)
    local = run_study(path, tmp_path / "local", workers=2, progress=None)
    out = tmp_path / "dask"
    assert main(["study", str(path), "--out", str(out), "--scheduler", address]) == 0
    assert "ran        12 cases in" in capsys.readouterr().out
    remote = load_results(out)
    pd.testing.assert_frame_equal(
        remote.drop(columns="run_time_s"), local.table.drop(columns="run_time_s")
    )
    assert list(remote["status"]).count("failed") == 4
    assert (remote["run_time_s"] > 0).all()
    study = json.loads((out / "study.json").read_text())
    assert study == json.loads((tmp_path / "local" / "study.json").read_text())


def test_killing_a_worker_in_the_middle_loses_no_case(cluster, tmp_path) -> None:
    from distributed import Client

    address, folder = cluster
    # The victim's cases never end (tests/dask_stall.py): it dies holding one.
    victim_folder = tmp_path / "victim"
    victim_folder.mkdir()
    stall = Path(__file__).with_name("dask_stall.py")
    victim = start_worker(address, "victim", victim_folder, preload=stall)
    path = write_study(tmp_path, grid_study(16, t_end="0.1 s"))
    out = tmp_path / "out"
    with Client(address, timeout="60s") as client, ThreadPoolExecutor(1) as pool:
        client.wait_for_workers(3, timeout=60)
        running = pool.submit(run_study, path, out, scheduler=address, progress=None)
        deadline = time.monotonic() + 600  # a hung cluster, not a slow machine
        while not list(victim_folder.glob("started_case_*")):
            assert time.monotonic() < deadline and not running.done()
            time.sleep(0.01)
        victim.kill()  # in the middle of a case
        victim.wait(timeout=20)
        run = running.result(timeout=300)
    assert run.complete and run.missing == {}
    cases = [json.loads(line)["case"] for line in (out / "cases.jsonl").read_text().splitlines()]
    assert sorted(cases) == list(range(16))  # every case exactly once
    assert list(run.table["case"]) == list(range(16))
    assert set(run.table["status"]) == {"finished"}
