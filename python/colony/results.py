"""Run and sweep folders into pandas (docs/data-output.md, docs/sweeps.md).

    run = colony.results.load_run("runs/my-run")
    run.summary            # dict, summary.json
    run.metrics            # DataFrame: tick, time, one column per metric
    run.trajectories       # DataFrame from trajectories.csv, .csv.gz or .h5 (None if not recorded)

    sweep = colony.results.load_sweep("sweeps/scal")
    sweep.results          # one row per run: run, its parameters (typed), seed, status, final metrics
    sweep.timeseries       # long form: run, parameters, seed, tick, time, metric, value

pandas (python3-pandas) is imported when a table is first read; HDF5 trajectories need h5py
(python3-h5py).
"""

import functools
import json
import os
import xml.etree.ElementTree as ElementTree

__all__ = ["Run", "Sweep", "load_run", "load_sweep"]


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("colony.results needs pandas (Debian: python3-pandas)") from e
    return pandas


def _need_folder(folder, what, marker):
    folder = os.fspath(folder)
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{what} folder '{folder}' does not exist")
    if not os.path.exists(os.path.join(folder, marker)):
        raise FileNotFoundError(
            f"'{folder}' is not a {what} folder: it has no {marker}")
    return folder


def _read_metrics(path):
    """metrics.csv: tick as int64, time and the metrics as float64."""
    pd = _pandas()
    df = pd.read_csv(path, float_precision="round_trip")
    df["tick"] = df["tick"].astype("int64")
    return df


class Run:
    """One run folder (colony run --out FOLDER, or a sweep's runs/NAME). Tables are read when
    first asked for, then kept."""

    def __init__(self, folder):
        self.folder = _need_folder(folder, "run", "experiment.xml")

    def _path(self, name):
        return os.path.join(self.folder, name)

    @functools.cached_property
    def summary(self):
        """summary.json as a dict (None while the run has not ended: it is written last)."""
        path = self._path("summary.json")
        if not os.path.exists(path):
            return None
        with open(path, encoding="utf-8") as f:
            return json.load(f)

    @functools.cached_property
    def metrics(self):
        """metrics.csv: tick (int64), time (s) and the loop functions' metrics (float64)."""
        path = self._path("metrics.csv")
        return _read_metrics(path) if os.path.exists(path) else None

    @functools.cached_property
    def hashes(self):
        """hashes.csv: tick (int64), state_hash (str), or None."""
        path = self._path("hashes.csv")
        if not os.path.exists(path):
            return None
        return _pandas().read_csv(path, dtype={"tick": "int64", "state_hash": str})

    @functools.cached_property
    def trajectories(self):
        """The trajectories table (trajectories.csv, .csv.gz or .h5): tick (int64), time, id and
        type (str), x, y, z, yaw [, pitch, roll] (float64), then the robots' values; None when
        the run recorded none."""
        pd = _pandas()
        for name in ("trajectories.csv", "trajectories.csv.gz"):
            path = self._path(name)
            if os.path.exists(path):
                # round_trip: every number as the double it was written from.
                df = pd.read_csv(path, dtype={"id": str, "type": str}, float_precision="round_trip")
                df["tick"] = df["tick"].astype("int64")
                return df
        path = self._path("trajectories.h5")
        if not os.path.exists(path):
            return None
        try:
            import h5py
        except ImportError as e:  # pragma: no cover - depends on the machine
            raise ImportError(f"reading {path} needs h5py (Debian: python3-h5py)") from e
        with h5py.File(path, "r") as f:
            df = pd.DataFrame(f["trajectories"][:])
        # id and type are fixed-width bytes, labels variable-length: all UTF-8.
        for column in df.columns:
            if df[column].dtype.kind in "SO":
                df[column] = [v.decode("utf-8") if isinstance(v, bytes) else v
                              for v in df[column]]
        return df

    def __repr__(self):
        return f"<colony.results.Run {self.folder!r}>"


_TEXT_COLUMNS = {"run", "status", "final_state_hash", "code", "detail"}
_INT_COLUMNS = {"seed", "ticks", "robots"}


def _typed(values):
    """A column of text from results.csv as the type its values share: int64 when every value is
    a whole number (nullable Int64 when some cells are empty), float64 when every one is a number,
    bool for true/false, else str."""
    pd = _pandas()
    empty = values == ""
    present = values[~empty]
    if present.empty:
        return values.astype(str)
    if present.str.fullmatch(r"[+-]?\d+").all():
        numbers = pd.to_numeric(values.mask(empty))
        return numbers.astype("Int64") if empty.any() else numbers.astype("int64")
    if not pd.to_numeric(present, errors="coerce").isna().any():
        return pd.to_numeric(values.mask(empty)).astype("float64")
    if present.isin(["true", "false"]).all() and not empty.any():
        return values == "true"
    return values.astype(str)


class Sweep:
    """A sweep folder (colony sweep --out FOLDER): the manifest sweep.xml and results.csv."""

    def __init__(self, folder):
        self.folder = _need_folder(folder, "sweep", "sweep.xml")
        manifest = ElementTree.parse(os.path.join(self.folder, "sweep.xml")).getroot()
        self.params = [p.get("path") for p in manifest.iter("param")]
        self.experiment = manifest.get("experiment")

    @functools.cached_property
    def results(self):
        """results.csv, one row per run: run (str), one column per parameter (named by its path,
        typed from its values: int64, float64, bool or str), seed (int64), status (str), the
        run's numbers (float64, ticks and robots int64), final_state_hash and code (str),
        stale (bool), the loop functions' final metrics (float64), detail (str)."""
        pd = _pandas()
        path = os.path.join(self.folder, "results.csv")
        if not os.path.exists(path):
            raise FileNotFoundError(
                f"{path} does not exist: the sweep has not finished any run yet (or run "
                f"'colony sweep --collect' for an array job)")
        raw = pd.read_csv(path, dtype=str, keep_default_na=False)
        df = pd.DataFrame(index=raw.index)
        for column in raw.columns:
            values = raw[column]
            if column in _TEXT_COLUMNS:
                df[column] = values.astype(str)
            elif column == "stale":
                df[column] = values == "true"
            elif column in self.params or column in _INT_COLUMNS:
                df[column] = _typed(values)
            else:
                numbers = pd.to_numeric(values.mask(values == ""), errors="coerce")
                keep_text = numbers.isna() & ~values.isin(["", "nan", "NaN"])
                df[column] = values.astype(str) if keep_text.any() else numbers.astype("float64")
        return df

    def run(self, name):
        """The Run of results.csv's row `name` (its run column)."""
        return Run(os.path.join(self.folder, "runs", name))

    @functools.cached_property
    def timeseries(self):
        """Every run's metrics.csv in long form: run (str), the parameters and seed as in
        results, tick (int64), time (float64), metric (str), value (float64); runs in results
        order."""
        pd = _pandas()
        results = self.results
        keys = ["run"] + [p for p in self.params if p in results.columns] + ["seed"]
        frames = []
        for name in results["run"]:
            path = os.path.join(self.folder, "runs", name, "metrics.csv")
            if not os.path.exists(path):
                continue
            wide = _read_metrics(path)
            long = wide.melt(id_vars=["tick", "time"], var_name="metric", value_name="value")
            long.insert(0, "run", name)
            frames.append(long)
        columns = keys + ["tick", "time", "metric", "value"]
        if not frames:
            return pd.DataFrame({c: pd.Series(dtype=results[c].dtype if c in results else "float64")
                                 for c in columns})
        long = pd.concat(frames, ignore_index=True)
        long["metric"] = long["metric"].astype(str)
        long["value"] = long["value"].astype("float64")
        return long.merge(results[keys], on="run", how="left")[columns]

    def __repr__(self):
        return f"<colony.results.Sweep {self.folder!r}: parameters {', '.join(self.params)}>"


def load_run(folder):
    """The run folder `folder` (it holds experiment.xml): summary, metrics, trajectories."""
    return Run(folder)


def load_sweep(folder):
    """The sweep folder `folder` (it holds sweep.xml): results, timeseries, params."""
    return Sweep(folder)
