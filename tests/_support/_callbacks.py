"""What every test of a failing Python load or element function expects: a
``SolverError(reason="callback")`` chained to the function's own exception, whose message
carries the cause's, with the history computed before it kept."""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator
from typing import Any

import pytest

import duhamel


@contextlib.contextmanager
def callback_failure(cause: type[BaseException], match: str = "") -> Iterator[Any]:
    """Expects the block to raise ``SolverError(reason="callback")`` from a `cause`
    exception whose message matches `match` (searched in the SolverError's message too)."""
    with pytest.raises(duhamel.SolverError) as info:
        yield info
    err = info.value
    assert err.reason == "callback", err.reason
    assert isinstance(err.__cause__, cause), repr(err.__cause__)
    assert re.search(match, str(err.__cause__)), str(err.__cause__)
    assert re.search(match, str(err)), str(err)
    assert err.partial is not None and err.step is not None
