import ast
import json
from pathlib import Path

import numpy as np
import pytest

import comcore
from comcore import Status
from comcore.active._stop import STATUSES
from comcore.cli._outputs import STATUS_MEANINGS
from comcore.goal._session import GOAL_STATUSES
from comcore.paper._heatmap import UNCHECKED

PACKAGE = Path(comcore.__file__).parent


def test_a_status_is_its_string_in_comparisons_json_and_print():
    assert Status.OK == "ok" and json.dumps({"s": Status.BUDGET}) == '{"s": "budget"}'
    assert f"{Status.INCONSISTENT}" == str(Status.INCONSISTENT) == "inconsistent"
    assert repr(Status.LOST) == "'lost'"


def test_every_status_set_or_listed_by_the_library_is_a_member():
    listed = [*STATUSES, *GOAL_STATUSES, UNCHECKED, *STATUS_MEANINGS]
    assert all(isinstance(s, Status) for s in listed)


def _status_literals(source: str) -> list[int]:
    """Lines of ``status=<string>`` keywords and ``<...status...> == <string>`` comparisons."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.keyword) and node.arg == "status":
            values = [node.value]
        elif isinstance(node, ast.Compare) and "status" in ast.unparse(node.left):
            values = node.comparators
        else:
            continue
        found += [
            v.lineno for v in values if isinstance(v, ast.Constant) and isinstance(v.value, str)
        ]
    return found


def test_a_status_literal_is_found():
    assert sorted(_status_literals('f(status="ok")\nif est.status == "budget": pass\n')) == [1, 2]


def test_the_library_spells_no_status_as_a_string_literal():
    found = [
        f"{path.relative_to(PACKAGE)}:{line}"
        for path in sorted(PACKAGE.rglob("*.py"))
        for line in _status_literals(path.read_text())
    ]
    assert not found, found


def test_an_estimate_takes_a_members_string_and_refuses_another():
    region = np.ones((2, 2), bool)
    est = comcore.Estimate((0.0, 0.0), (0.0, 0.0), region, status="budget")
    assert est.status is Status.BUDGET and not est.ok
    with pytest.raises(ValueError, match=r"Estimate.status must be a comcore.Status, one of \["):
        comcore.Estimate((0.0, 0.0), (0.0, 0.0), region, status="contradiction")


def test_alg2_pushes_that_contradict_each_other_are_inconsistent():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    est = comcore.estimate_progressive(
        mask, [(0, 8, 30, 8), (0, 18, 30, 18)], [(0.2, 3, 0), (-0.2, 3, 0)]
    )
    assert est.status is Status.INCONSISTENT and not est.ok


def test_every_final_status_of_the_sessions_and_estimators_is_a_member():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    cases = [
        comcore.estimate_heatmap(mask, [], []),
        comcore.estimate_progressive(mask, [], []),
        comcore.estimate_posterior(mask, [(0, 13, 30, 13)], [(0.0, 0.0, 0.0)], model=None),
        comcore.ActiveSession(mask, model=None, rng=0),
    ]
    assert all(type(c.status) is Status for c in cases)


def test_wide_is_a_member_whose_meaning_and_mapping_are_documented():
    assert Status.WIDE == "wide" and Status.check("wide") is Status.WIDE
    doc = Status.__doc__
    assert 'WIDE : "wide"' in doc and "region is wider than the target" in doc
    # the mapping: the sessions' wide stops and the offline "wide" in one table
    assert "| ``estimate_posterior``, ``comcore estimate`` | ``ok`` | ``wide`` |" in doc
    assert "``budget``, ``exhausted``, ``uninformative``" in doc
    assert comcore.StopRule().target_radius == comcore._status.DEFAULT_TARGET_RADIUS == 0.006
