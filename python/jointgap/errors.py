"""The exceptions and warnings of jointgap, in one place (as ``jointgap.errors``; each is
also importable from the package root and from the module that raises it).

Errors of input name the offending item and value (file and line where there is one);
an error that stops work already done carries that work (:class:`RunStopped`,
:class:`BatchInterrupted`). Warnings are raised with :func:`warnings.warn` for a caller
to see or filter; the ``jointgap`` command prints them on stderr.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ._output_size import OUTPUT_MEMORY_FRACTION, OutputSize, _bytes
from .results import Result

__all__ = [
    "BatchInterrupted",
    "CalibrationError",
    "ComparisonWarning",
    "MeasuredDataError",
    "ModelError",
    "OutputTooLarge",
    "ReportError",
    "RunStopped",
    "RunWarning",
    "StudyError",
    "UnitError",
]

# ---------------------------------------------------------------------- invalid input


class ModelError(ValueError):
    """An invalid model: names the file and line (when known), the element and the problem.

    ``str(error)`` reads ``file:line: kind 'name': problem``; the parts are also
    attributes: ``file``, ``line``, ``kind`` (body, joint, driver, force, ground, model),
    ``name``, ``index`` (position of the element among those of its kind), ``key`` (the
    field, dotted for nested ones like ``profile.speed``) and ``problem``.
    """

    def __init__(
        self,
        problem: str,
        *,
        kind: str | None = None,
        name: str | None = None,
        index: int | None = None,
        key: str | None = None,
        file: str | None = None,
        line: int | None = None,
        related: tuple[str, int] | None = None,
    ) -> None:
        self.problem = problem
        self.kind = kind
        self.name = name
        self.index = index
        self.key = key
        self.file = file
        self.line = line
        self.related = related
        super().__init__(self._message())

    @property
    def element(self) -> str:
        """The element as the message names it, e.g. ``joint 'crank_rod'`` or ``body #2``."""
        if self.kind is None:
            return ""
        if self.name:
            return f"{self.kind} '{self.name}'"
        if self.index is not None:
            return f"{self.kind} #{self.index + 1}"
        return self.kind

    def _message(self) -> str:
        where = ""
        if self.file is not None:
            where = f"{self.file}:{self.line}: " if self.line is not None else f"{self.file}: "
        element = self.element
        return f"{where}{element}: {self.problem}" if element else f"{where}{self.problem}"

    def located(self, file: str, line: int | None, problem: str | None = None) -> ModelError:
        """The same error with its file and line (and optionally a reworded problem)."""
        return ModelError(
            self.problem if problem is None else problem,
            kind=self.kind,
            name=self.name,
            index=self.index,
            key=self.key,
            file=file,
            line=line,
            related=self.related,
        )

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self.problem, self.__dict__.copy()))


ModelError.__module__ = "jointgap"  # shown as jointgap.ModelError in tracebacks


def _rebuild(problem: str, attrs: dict[str, Any]) -> ModelError:
    attrs = {k: v for k, v in attrs.items() if k != "problem"}
    return ModelError(problem, **attrs)


class UnitError(ValueError):
    """A quantity that cannot be read: malformed number, unknown unit or wrong dimension."""


class StudyError(ValueError):
    """An invalid study file: the message names the file, line, key and value."""


class MeasuredDataError(ValueError):
    """A measured record that cannot be used; the message names the file and line."""


# ---------------------------------------------------------------------- runs and their outcomes


class OutputTooLarge(ValueError):
    """A run refused before it starts because its samples would not fit in memory: the
    message gives the figure, the limit and the ways out.

    Attributes:
        size: the expected output (of all the runs of a batch together).
        limit: the limit [bytes], :data:`OUTPUT_MEMORY_FRACTION` of the memory.

    The message starts with ``options``, the options it concerns.
    """

    def __init__(
        self, size: OutputSize, limit: int, memory: int, options: Mapping[str, Any]
    ) -> None:
        self.size = size
        self.limit = limit
        given = f"t_end = {options['t_end']:g} s, rate = {options['rate']:g} Hz"
        super().__init__(
            f"options {given}: the output would take {size.describe()}, above the limit of "
            f"{_bytes(limit)} ({OUTPUT_MEMORY_FRACTION:g} of this machine's {_bytes(memory)} "
            "of memory): "
            "sample at a lower rate (--rate, rate=), keep every K-th sample (--decimate K, "
            "decimate=K), record fewer channels (--channel, channels=), or write the samples "
            "to disk as the run goes (--stream, stream=PATH)"
        )


class RunStopped(ValueError):
    """A run of the check stopped early: no verdict; ``result`` holds what it computed."""

    def __init__(self, message: str, result: Result) -> None:
        super().__init__(message)
        self.result = result


class BatchInterrupted(KeyboardInterrupt):
    """Ctrl-C (or a KeyboardInterrupt raised by ``progress``) stopped a batch.

    It is a KeyboardInterrupt, so a script stops as it would anywhere else; what the
    batch computed is kept in :attr:`results`.

    Attributes:
        results: in the order of the models: the :class:`Result` of each run that ended
            (status ``finished`` or ``failed``) or that Ctrl-C stopped (status
            ``interrupted``, with what it computed up to there), the :class:`ModelError`
            of each model refused, and None for each model whose run had not started.
    """

    def __init__(self, results: list[Result | Exception | None]) -> None:
        done = [r for r in results if r is not None]
        stopped = sum(isinstance(r, Result) and r.interrupted for r in done)
        super().__init__(
            f"batch interrupted by Ctrl-C: {len(done) - stopped} of {len(results)} runs ended, "
            f"{stopped} stopped with status interrupted, {len(results) - len(done)} not started"
        )
        self.results = results


class CalibrationError(ValueError):
    """The calibration cannot start or cannot go on (its message says which run)."""


class ReportError(ValueError):
    """A result or folder that cannot be drawn; the message names what is missing."""


# ---------------------------------------------------------------------- warnings


class RunWarning(UserWarning):
    """A note about a run that its :attr:`Result.warnings` also holds (e.g. impacts that
    fell between output samples): raised by :meth:`jointgap.Model.simulate` for the
    caller to see; the ``jointgap run`` command prints it in its summary."""


class ComparisonWarning(UserWarning):
    """A comparison that runs but may mislead: a unit of the same quantity that differs
    from the channel's, a record shorter than the lag search window."""
