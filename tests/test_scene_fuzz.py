"""Property-based: whatever a user puts into a scene or --set, only SceneError (exit 2) comes out."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import _cli
from rods.scene import SCHEMA, SceneError, scene_from_dict

values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.booleans(),
    st.text(max_size=12),
    st.lists(st.one_of(st.text(max_size=6), st.floats()), max_size=3),
    st.dictionaries(st.text(max_size=5), st.integers(), max_size=2),
)
keys = st.one_of(st.sampled_from(sorted(SCHEMA)), st.text(min_size=1, max_size=15))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=keys, value=values)
def test_any_value_in_a_file_is_accepted_or_refused_cleanly(paper_dict, key, value):
    import copy

    d = copy.deepcopy(paper_dict)
    node = d
    *parents, leaf = key.split(".")
    try:
        for p in parents:
            node = node.setdefault(p, {})
        node[leaf] = value
    except (AttributeError, TypeError):
        return  # the key path runs through a non-table value: not a scene anyone can write
    try:
        s = scene_from_dict(d)
    except SceneError as e:
        assert e.key and "scene key" in str(e)
        return
    assert s.speed > 0 and math.isfinite(s.speed)


@settings(max_examples=200, deadline=None)
@given(key=keys, raw=st.text(max_size=20))
def test_any_override_string_exits_0_or_2(key, raw):
    try:  # argparse itself may refuse the token (e.g. "-="): that is exit 2 too
        args = _cli.parser("fuzz").parse_args(["--set", f"{key}={raw}"])
        _cli.load(args)
    except SystemExit as e:
        assert e.code == 2


def test_cli_load_exit_code():
    args = _cli.parser("x").parse_args(["--set", "impact.speed=-1"])
    with pytest.raises(SystemExit) as e:
        _cli.load(args)
    assert e.value.code == 2
