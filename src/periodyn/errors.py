"""Errors that periodyn raises on purpose: each message names the problem and the fix."""


class InputError(ValueError):
    """Bad input (shape, value, sign, unknown option); the message says what to change."""


class ConvergenceError(RuntimeError):
    """An iteration (Newton, eigen-solve, integrator) failed; never returned as a result.

    Attributes: ``residual`` (last residual norm), ``iterations`` (count done).
    """

    def __init__(self, message: str, residual: float = float("nan"), iterations: int = 0):
        super().__init__(message)
        self.residual = residual
        self.iterations = iterations
