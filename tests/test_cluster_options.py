"""Runtime settings to ensemble options (noslipsim.cluster): defaults, errors, the resumable chunk folder.

The settings themselves are exercised on real clusters in test_distributed.py and test_slurm.py;
here, what needs no cluster: the workflow schema and the package agree on every setting and
default, bad settings fail with one clear line, and the chunk folder of a job is its own,
kept when the job fails (so that its rerun resumes) and removed when it succeeds.
"""
from pathlib import Path

import pytest
import yaml

from noslipsim.cluster import RUNTIME_DEFAULTS, ensemble_options, runtime_settings

SCHEMA = Path(__file__).resolve().parents[1] / "workflow" / "schemas" / "config.schema.yaml"


def test_the_schema_declares_every_setting_with_the_package_default():
    runtime = yaml.safe_load(SCHEMA.read_text())["properties"]["runtime"]["properties"]
    assert {k: v["default"] for k, v in runtime.items()} == RUNTIME_DEFAULTS


@pytest.mark.parametrize("runtime, match", [
    ({"dask_schedular": "tcp://127.0.0.1:1"}, "unknown settings.*dask_schedular"),
    ({"dask_cluster": "pbs"}, "dask_cluster: expected one of"),
    ({"dask_cluster": "slurm", "dask_scheduler": "tcp://127.0.0.1:1"}, "not both"),
    ({"dask_workers": "two"}, "dask_workers: expected a positive integer"),
    ({"chunk_size": "0"}, "chunk_size: expected a positive integer"),
    ({"dask_worker_timeout": "-1"}, "dask_worker_timeout: expected a positive number"),
])
def test_bad_settings_fail_with_one_line(runtime, match):
    with pytest.raises(ValueError, match=match):
        runtime_settings(runtime)


def test_command_line_strings_are_read_as_numbers_and_null():
    """snakemake --config 'runtime={dask_workers: 4, chunk_size: null}' gives {'dask_workers': '4', ...}."""
    got = runtime_settings({"dask_workers": "4", "chunk_size": "null", "dask_worker_timeout": "2.5",
                            "dask_scheduler": "null"})
    assert got["dask_workers"] == 4 and got["chunk_size"] is None and got["dask_worker_timeout"] == 2.5
    assert got["dask_scheduler"] is None


def test_no_settings_mean_local_threads_in_memory():
    with ensemble_options(None, 3) as how:
        assert how == {"scheduler": None, "num_workers": 3, "chunk_size": None, "progress": True}
    with ensemble_options({"dask_scheduler": "tcp://127.0.0.1:1", "chunk_size": 7}, 2) as how:
        assert how["scheduler"] == "tcp://127.0.0.1:1" and how["chunk_size"] == 7


def test_the_chunk_folder_is_per_rule_and_science_kept_on_failure_removed_on_success(tmp_path):
    runtime = {"chunk_folder": str(tmp_path)}
    with ensemble_options(runtime, 1) as how:
        assert "out" not in how                                        # no name: no on-disk path
    with ensemble_options(runtime, 1, name="rule", params={"n": 1}) as a, \
            ensemble_options(runtime, 1, name="rule", params={"n": 2}) as b:
        assert Path(a["out"]).parent == tmp_path / "rule" and a["out"] != b["out"]
    with pytest.raises(RuntimeError):
        with ensemble_options(runtime, 1, name="rule", params={"n": 1}) as how:
            Path(how["out"]).mkdir(parents=True)
            raise RuntimeError("the job died")
    assert Path(how["out"]).is_dir()                                   # kept: the rerun resumes
    with ensemble_options(runtime, 1, name="rule", params={"n": 1}) as again:
        assert again["out"] == how["out"]
    assert not Path(how["out"]).exists()                               # the dataset is written: gone
