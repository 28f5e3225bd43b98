"""Fixtures shared by the test modules."""

import pytest


class Interrupted(Exception):
    """Stands for a killed process: raised from a run's ``on_step`` once a chosen step has converged."""


class Interrupter:
    """``interrupt_after(k)``: an ``on_step`` callback that raises :attr:`error` once step ``k`` has converged."""

    error = Interrupted

    def __call__(self, step: int):
        def on_step(result):
            if len(result.load_factors) - 1 == step:
                raise Interrupted
        return on_step


@pytest.fixture
def interrupt_after():
    return Interrupter()
