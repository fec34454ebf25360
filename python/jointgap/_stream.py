"""Results streamed to disk: a long run writes its samples to a Parquet file in chunks
as it goes, so that memory holds one chunk, not the run.

The engine hands every chunk of samples to a :class:`ParquetSink` (one row group per
chunk, columns ``time`` then the channels); the :class:`~jointgap.Result` of the run
reads its channels back from the file one at a time (:class:`StoredChannels`)::

    result = model.simulate(60, rate=10_000, stream="run.parquet")
    result["slider.ax"]          # read from run.parquet, this channel only

Memory is what this module is for, so it keeps pyarrow from importing pandas (about
45 MB): ``pa.array`` and ``Array.to_numpy`` import it to inspect their argument, so
columns go to Arrow and back over their own buffers, without a copy
(:func:`arrow_column`, :func:`numpy_column`).
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = [
    "ParquetSink",
    "StoredChannels",
    "arrow_column",
    "numpy_column",
    "read_column",
    "read_time",
]


class ParquetSink:
    """Writes sample chunks ``(names, time, data[n_channels, n])`` as row groups of a
    Parquet file with columns ``time`` and the channels; the file is complete after
    :meth:`close`. Without dictionary encoding, which float samples rarely repeat enough
    for: the file is about a fifth smaller, written faster and with smaller buffers."""

    def __init__(self, path: str | PathLike[str]) -> None:
        self.path = Path(path)
        self.channels: list[str] = []
        self.samples = 0
        self._schema: Any = None
        self._writer: Any = None

    def __call__(
        self, names: Sequence[str], time: npt.NDArray[np.float64], data: npt.NDArray[np.float64]
    ) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        if self._writer is None:
            self.channels = list(names)
            self._schema = pa.schema([(name, pa.float64()) for name in ["time", *names]])
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._writer = pq.ParquetWriter(
                self.path, self._schema, compression="zstd", use_dictionary=False
            )
        columns = [arrow_column(time), *(arrow_column(row) for row in data)]
        self._writer.write_batch(pa.RecordBatch.from_arrays(columns, schema=self._schema))
        self.samples += len(time)

    def close(self, names: Sequence[str] = ()) -> None:
        """Finishes the file; ``names`` are the run's channels, for a run that ended
        before its first sample (no file when they are not known)."""
        if self._writer is None and names:
            self(names, np.zeros(0), np.zeros((len(names), 0)))
        if self._writer is not None:
            self._writer.close()


def read_time(path: str | PathLike[str]) -> npt.NDArray[np.float64]:
    """The ``time`` column of a streamed file."""
    return read_column(path, "time")


def read_column(path: str | PathLike[str], name: str) -> npt.NDArray[np.float64]:
    """One column of a Parquet file as float64, read one row group at a time into the
    array it returns (reading the whole column first would hold it twice); KeyError when
    the file has no such column."""
    import pyarrow.parquet as pq

    with pq.ParquetFile(path, pre_buffer=False) as file:
        if name not in file.schema_arrow.names:
            raise KeyError(f"{path}: no column {name!r}")
        column = np.empty(file.metadata.num_rows)
        at = 0
        for group in range(file.num_row_groups):
            table = file.read_row_group(group, columns=[name], use_threads=False)
            for chunk in table.column(0).chunks:
                column[at : at + len(chunk)] = numpy_column(chunk)
                at += len(chunk)
    return column


def arrow_column(values: npt.NDArray[np.float64]) -> Any:
    """A float64 Arrow array over the memory of ``values`` (``pa.array`` would import
    pandas to check its argument's type)."""
    import pyarrow as pa

    values = np.ascontiguousarray(values, dtype=np.float64)
    return pa.Array.from_buffers(pa.float64(), len(values), [None, pa.py_buffer(values)])


def numpy_column(chunk: Any) -> npt.NDArray[np.float64]:
    """The values of an Arrow array as float64: a view of its buffer when it is float64
    without nulls (as :class:`ParquetSink` writes), else converted (nulls become NaN)."""
    import pyarrow as pa

    if len(chunk) == 0:
        return np.zeros(0)
    if chunk.type == pa.float64() and chunk.null_count == 0:
        start = chunk.offset * 8
        return np.frombuffer(chunk.buffers()[1], dtype=np.float64, count=len(chunk), offset=start)
    return np.asarray(chunk.to_numpy(zero_copy_only=False), dtype=np.float64)


class StoredChannels:
    """The channels of a streamed result, read from its Parquet file on demand: indexing
    with a channel's position reads that column only; :meth:`__array__` reads them all."""

    def __init__(self, path: str | PathLike[str], channels: Sequence[str], n_samples: int) -> None:
        self.path = Path(path)
        self.channels = list(channels)
        self.shape = (len(self.channels), n_samples)

    def __len__(self) -> int:
        return self.shape[0]

    def __getitem__(self, k: int) -> npt.NDArray[np.float64]:
        column = read_column(self.path, self.channels[k])
        column.flags.writeable = False
        return column

    def __array__(self, dtype: Any = None, copy: Any = None) -> npt.NDArray[np.float64]:
        table = np.empty(self.shape, dtype=float)
        for k in range(len(self.channels)):
            table[k] = self[k]
        return table if dtype is None else table.astype(dtype)
