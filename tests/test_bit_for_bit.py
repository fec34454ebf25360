"""Every planar result stays what it was, bit for bit (fingerprints in tests/records/).

A change that moves no physics (a new layout of the engine, a faster evaluation) must
reproduce every recorded channel, sample time, impact and run counter of
:mod:`planar_records`'s cases exactly. A change that moves results on purpose records
the fingerprints anew and explains the difference in its commit.
"""

from __future__ import annotations

import json

import pytest
from planar_records import RECORDS, cases, differences, fingerprint, instruction_set

FILE = json.loads(RECORDS.read_text())
RECORDED = FILE["cases"]
CASES = dict(cases())


def test_every_case_is_recorded() -> None:
    assert sorted(CASES) == sorted(RECORDED)


@pytest.mark.parametrize("name", sorted(CASES))
def test_run_is_bit_identical(name: str, engine: object) -> None:
    if instruction_set() != FILE["instruction_set"]:
        pytest.skip(f"recorded on {FILE['instruction_set']}, this machine is {instruction_set()}")
    assert differences(RECORDED[name], fingerprint(CASES[name]())) == []
