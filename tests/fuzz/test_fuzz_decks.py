"""The deck fuzzer: hostile decks made from small copies of the examples (values, keys
and sections changed with hypothesis, and damaged bytes) run through ``peridynamics
check --bonds`` and a few 10-step ``run`` s in this process; each must end with a clean
exit (0 or 2; 3 for an unstable run), no traceback, and finite results
(:mod:`tests.fuzz.harness`).

Two sizes: the default selection runs a bounded, derandomised fuzz (the same examples
on every machine, about 20 s); ``pytest -m long`` runs a longer one from the seed
``LONG_SEED`` (``PERIDYNAMICS_FUZZ_SEED=random`` draws one and prints it,
``PERIDYNAMICS_FUZZ_SEED=<seed>`` repeats it). A failure prints
the deck's text; ``tests/hostile/cases_decks.yaml`` keeps the decks found so far.
"""

from __future__ import annotations

import os
import random
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

from tests.fuzz.harness import Tally, exercise
from tests.fuzz.mutations import BASES, damaged_bytes, mutated_deck

#: the long tier's seed in CI (reproducible: a random seed there made two CI runs fail on
#: what it happened to find); ``PERIDYNAMICS_FUZZ_SEED=random`` explores, any integer
#: repeats a run
LONG_SEED = 4242
#: examples per test: the default selection, and the long tier (the default's 10 runs
#: reach all six RUN_BASES; each run past the first of its base costs about 0.3 s)
DEFAULT = {"mutated": 300, "bytes": 200, "run": 10}
LONG = {"mutated": 3500, "bytes": 2000, "run": 300}
#: the bases of the short runs (explicit solvers: a 10-step run takes milliseconds)
RUN_BASES = (
    "bar_wave_1d/deck.yaml",
    "spalling/test_bar_fdm_pd3.yaml",
    "waves/blast_bar_1kg.yaml",
    "research/notched_plate.yaml",
    "rock_compression/flaw45.yaml",
    "bodies/three_point_bend_softening.yaml",
)
#: the mutations of a run deck: mostly values of their own kind (to run, not be refused)
RUN_OPS = ("leaf", "leaf", "leaf", "insert", "graft")
#: what every run deck keeps, whatever the mutation: 10 steps, no figures or frames
RUN_FIXED = {"solver.end_time": None, "solver.steps": 10, "output.plot": "none",
             "output.vtk_every": 0}  # fmt: skip


def fuzz(
    strategy: st.SearchStrategy[Any], body: Callable[[Any], None], examples: int, long: bool
) -> None:
    """Run ``body`` on ``examples`` examples of ``strategy``: derandomised by default;
    from a random seed (printed) in the long tier."""
    config = settings(
        max_examples=examples,
        deadline=None,
        derandomize=not long,
        database=None,
        suppress_health_check=list(HealthCheck),
        print_blob=False,
    )
    test = config(given(strategy)(body))
    if long:
        asked = os.environ.get("PERIDYNAMICS_FUZZ_SEED") or str(LONG_SEED)
        chosen = random.randrange(2**32) if asked == "random" else int(asked)
        print(f"fuzz seed: {chosen} (repeat: PERIDYNAMICS_FUZZ_SEED={chosen})")
        test = seed(chosen)(test)
    test()


def _mutated(examples: int, long: bool) -> Tally:
    tally = Tally()

    def body(case: tuple[tuple[str, str], bool]) -> None:
        (_, text), bonds = case  # check --bonds, or check alone (its own size checks)
        exercise(text.encode("utf-8", errors="surrogatepass"), tally, bonds=bonds)

    fuzz(st.tuples(mutated_deck(), st.booleans()), body, examples, long)
    return tally


def _bytes(examples: int, long: bool) -> Tally:
    tally = Tally()

    def body(case: tuple[str, bytes]) -> None:
        exercise(case[1], tally)

    fuzz(damaged_bytes(), body, examples, long)
    return tally


def _runs(examples: int, long: bool) -> Tally:
    tally = Tally()
    strategy = mutated_deck(RUN_BASES, ops=RUN_OPS, fixed=RUN_FIXED)

    def body(case: tuple[str, str]) -> None:
        exercise(case[1].encode("utf-8", errors="surrogatepass"), tally, command="run")

    fuzz(strategy, body, examples, long)
    return tally


def test_bases_are_valid_and_small() -> None:
    """Each base deck is valid as the fuzzer makes it (so a mutation is what fails)."""
    from tests.fuzz.mutations import base, dump

    tally = Tally()
    for name in BASES:
        exercise(dump(base(name), []).encode(), tally)
    assert tally.exits == {0: len(BASES)}, tally.line("bases")


@pytest.mark.parametrize("kind", [pytest.param(k, id=k) for k in ("mutated", "bytes", "run")])
def test_fuzz_decks(kind: str) -> None:
    """The bounded fuzz of the default selection (derandomised)."""
    tally = {"mutated": _mutated, "bytes": _bytes, "run": _runs}[kind](DEFAULT[kind], False)
    print(tally.line(kind))


@pytest.mark.long
@pytest.mark.parametrize("kind", [pytest.param(k, id=k) for k in ("mutated", "bytes", "run")])
def test_fuzz_decks_long(kind: str) -> None:
    """The long fuzz of CI's ``long`` tier (seed ``LONG_SEED`` unless
    ``PERIDYNAMICS_FUZZ_SEED`` says otherwise; printed)."""
    tally = {"mutated": _mutated, "bytes": _bytes, "run": _runs}[kind](LONG[kind], True)
    print(tally.line(kind))
