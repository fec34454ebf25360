"""Results streamed to disk: a long run writes its samples to a Parquet file in chunks
as it goes, so that memory holds one chunk, not the run.

The engine hands every chunk of samples to a :class:`ParquetSink` (one row group per
chunk, columns ``time`` then the channels); the :class:`~jointgap.Result` of the run
reads its channels back from the file one at a time (:class:`StoredChannels`)::

    result = model.simulate(60, rate=10_000, stream="run.parquet")
    result["slider.ax"]          # read from run.parquet, this channel only
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["ParquetSink", "StoredChannels", "read_time"]


class ParquetSink:
    """Writes sample chunks ``(names, time, data[n_channels, n])`` as row groups of a
    Parquet file with columns ``time`` and the channels; the file is complete after
    :meth:`close`."""

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
            self._writer = pq.ParquetWriter(self.path, self._schema, compression="zstd")
        columns = [pa.array(time), *(pa.array(row) for row in data)]
        self._writer.write_table(pa.Table.from_arrays(columns, schema=self._schema))
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
    import pyarrow.parquet as pq

    column: npt.NDArray[np.float64] = pq.read_table(path, columns=["time"])["time"].to_numpy()
    return column


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
        import pyarrow.parquet as pq

        name = self.channels[k]
        column: npt.NDArray[np.float64] = pq.read_table(self.path, columns=[name])[name].to_numpy()
        column.flags.writeable = False
        return column

    def __array__(self, dtype: Any = None, copy: Any = None) -> npt.NDArray[np.float64]:
        table = np.empty(self.shape, dtype=float)
        for k in range(len(self.channels)):
            table[k] = self[k]
        return table if dtype is None else table.astype(dtype)
