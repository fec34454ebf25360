"""A Dask worker preload (``dask worker --preload``) for tests/test_study_dask.py: the
worker's study cases never end, after each one has said that it began by a file
``started_case_<k>`` in the worker's folder. The test kills such a worker while it runs
a case, at a moment the file fixes, not after a delay."""

from __future__ import annotations

import threading
from pathlib import Path

from jointgap.study import execute


def _stalled(case: execute.Case) -> execute.Outcome:
    Path(f"started_case_{case.case}").touch()
    threading.Event().wait()  # until the test kills this worker
    raise AssertionError("unreachable")


execute.run_case = _stalled
