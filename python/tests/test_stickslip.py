"""The Python package against the command line: the same rows, the same tables, the same errors
(the stages run in-process; the CLI here is the package's own console script, the Rust binary's
code)."""

import dataclasses
import json
import shutil
import subprocess
import sys
from pathlib import Path

import polars as pl
import pytest

import stickslip


def pq_metadata(path: Path) -> dict:
    pq = pytest.importorskip("pyarrow.parquet")
    return {k.decode(): v.decode() for k, v in pq.read_metadata(path).metadata.items()}


def cli(*args: str) -> subprocess.CompletedProcess:
    exe = shutil.which("stickslip")
    assert exe, "the package installs the stickslip console script"
    return subprocess.run([exe, *args], capture_output=True, text=True)


def test_simulate_equals_the_cli_dataset_of_the_paper_scenario(tmp_path: Path) -> None:
    r = cli("simulate", "--out", str(tmp_path / "d"), "--realizations", "18000", "--seed", "1")
    assert r.returncode == 0, r.stderr
    from_cli = pl.read_parquet(tmp_path / "d").sort("realization")
    from_python = stickslip.simulate(seed=1, realizations=18000)
    assert isinstance(from_python, pl.DataFrame) and from_python.height == 18000
    assert from_python.columns == from_cli.columns
    assert from_python.equals(from_cli), "every value of every column"
    # provenance: the part file's footer
    footer = pq_metadata(next((tmp_path / "d").glob("part-*.parquet")))
    assert stickslip.provenance(from_python)["stickslip.scenario"] == footer["stickslip.scenario"]
    with pytest.raises(stickslip.DatasetError, match="provenance"):
        stickslip.provenance(from_python.head(3))


def test_any_thread_count_gives_the_same_rows() -> None:
    one = pl.DataFrame(stickslip.simulate(realizations=3000, threads=1))
    two = pl.DataFrame(stickslip.simulate(realizations=3000, threads=2))
    assert one.equals(two)


def test_a_dict_toml_text_and_set_are_the_same_scenario() -> None:
    by_dict = stickslip.simulate({"model": {"damping": 0.5}, "run": {"realizations": 500}})
    by_text = stickslip.simulate(stickslip.Toml("[model]\ndamping = 0.5\n[run]\nrealizations = 500\n"))
    by_set = stickslip.simulate(set={"model.damping": 0.5}, realizations=500)
    frames = [pl.DataFrame(t) for t in (by_dict, by_text, by_set)]
    assert frames[0].equals(frames[1]) and frames[0].equals(frames[2])
    # and not the paper's rows
    assert not frames[0].equals(pl.DataFrame(stickslip.simulate(realizations=500)))


def test_analyze_tables_equal_the_cli_files(tmp_path: Path) -> None:
    data = tmp_path / "d"
    stickslip.simulate(realizations=4000, out=data)
    r = cli("analyze", str(data), "--out", str(tmp_path / "a"))
    assert r.returncode == 0, r.stderr
    a = stickslip.analyze(data)
    names = sorted(p.stem for p in (tmp_path / "a").glob("*.parquet"))
    assert sorted(a.tables) == names and "moments" in names
    for name in names:
        assert a.tables[name].equals(pl.read_parquet(tmp_path / "a" / f"{name}.parquet")), name
    # the typed summary is summary.json, field for field
    cli_summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert isinstance(a.summary, stickslip.Summary) and isinstance(a.summary.counts["S_T"].mean, float)
    assert json.loads(json.dumps(dataclasses.asdict(a.summary))) == cli_summary
    moments = a.moments
    st = moments.filter(pl.col("variable") == "S_T")
    assert st.height == 1 and 15 < st["mean"][0] < 18


def test_bad_input_raises_the_class_of_its_culprit_naming_it(tmp_path: Path) -> None:
    with pytest.raises(stickslip.ScenarioError, match="model.mass"):
        stickslip.simulate(set={"model.mass": -1.0}, realizations=10)
    with pytest.raises(stickslip.ScenarioError, match="belt.swich_rate"):
        stickslip.simulate({"belt": {"swich_rate": 1.0}})
    with pytest.raises(stickslip.ScenarioError, match="nope.toml"):
        stickslip.simulate(str(tmp_path / "nope.toml"))
    with pytest.raises(stickslip.UsageError, match="out=DIR"):
        stickslip.simulate(realizations=10**8)
    with pytest.raises(stickslip.DatasetError, match="no dataset part files"):
        stickslip.analyze(tmp_path)
    with pytest.raises(stickslip.UsageError, match="bins = -3"):
        stickslip.analyze(tmp_path, bins=-3)
    (tmp_path / "file").write_text("mine")
    with pytest.raises(stickslip.OutputError, match="file"):
        stickslip.simulate(realizations=10, out=tmp_path / "file")
    # each is a ValueError, as the command line's exit code 2; a failure while running is not
    for cls in (stickslip.UsageError, stickslip.ScenarioError, stickslip.DatasetError, stickslip.OutputError):
        assert issubclass(cls, ValueError)
    assert issubclass(stickslip.RunError, RuntimeError) and not issubclass(stickslip.RunError, ValueError)


def test_scenes_and_the_console_script() -> None:
    s = stickslip.scenes()
    assert list(s)[0] == "paper" and "markov_belt" in s and "[belt]" in s["paper"]
    r = cli("--version")
    assert r.returncode == 0 and "stickslip" in r.stdout
    r = cli("simulate", "--out")
    assert r.returncode == 2
    r = cli("simulate", "--out", "/tmp/x", "--set", "model.mass=-1")
    assert r.returncode == 2 and r.stderr.startswith("stickslip: error: ") and "model.mass" in r.stderr


def test_pyarrow_and_pandas_take_the_frame_as_the_readme_says() -> None:
    pytest.importorskip("pyarrow")
    df = stickslip.simulate(realizations=100)
    at = df.to_arrow()
    assert at.num_rows == 100 and "stick_duration" in at.column_names
    pd = pytest.importorskip("pandas")
    assert isinstance(df.to_pandas(), pd.DataFrame) and len(df.to_pandas()) == 100


def test_the_worked_example_runs(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    example = Path(__file__).resolve().parents[1] / "examples" / "paper.py"
    r = subprocess.run([sys.executable, str(example), str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "fig12.png").stat().st_size > 10_000
    # its dataset is the paper scenario's (seed 1, 18,000 realizations) and its Table 1 is what
    # `stickslip analyze` writes for it
    assert pl.read_parquet(tmp_path / "dataset").height == 18000
    a = cli("analyze", str(tmp_path / "dataset"), "--out", str(tmp_path / "cli-analysis"))
    assert a.returncode == 0, a.stderr
    moments = pl.read_parquet(tmp_path / "cli-analysis" / "moments.parquet")
    for variable, index in [("T", 1), ("D", 2), ("H", 6)]:
        mean = moments.filter((pl.col("variable") == variable) & (pl.col("index") == index))["mean"][0]
        assert f"{mean:.6f}" in r.stdout, (variable, index, mean)
    assert "switch_rate" in r.stdout


def interrupt_after(call: str, seconds: float) -> float:
    """Run ``call`` in a child Python, send it SIGINT after ``seconds``; assert it raised
    KeyboardInterrupt; return how long it took to end after the signal."""
    import signal
    import time

    code = f"import stickslip, sys\nprint('start', flush=True)\ntry:\n    {call}\nexcept KeyboardInterrupt:\n    print('interrupted', flush=True); sys.exit(7)\n"
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    assert p.stdout is not None and p.stdout.readline().strip() == "start"
    time.sleep(seconds)
    p.send_signal(signal.SIGINT)
    t0 = time.monotonic()
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 7 and "interrupted" in out
    return time.monotonic() - t0


def test_ctrl_c_interrupts_a_long_simulation() -> None:
    assert interrupt_after("stickslip.simulate(realizations=10**7)", 1.0) < 5, "noticed within a window of chunks"


def test_a_table_written_or_analysed_is_the_cli_dataset(tmp_path: Path) -> None:
    t = stickslip.simulate(realizations=3000, seed=4)
    stickslip.simulate(realizations=3000, seed=4, out=tmp_path / "cli")
    by_table = stickslip.analyze(t)
    by_dir = stickslip.analyze(tmp_path / "cli")
    for name in by_dir.tables:
        assert by_table.tables[name].equals(by_dir.tables[name]), name
    # the part file written from a table is the CLI's, byte for byte
    from stickslip import _stickslip

    path = _stickslip.write_table(stickslip._TABLES[id(t)], str(tmp_path / "from_table"))
    cli_part = next((tmp_path / "cli").glob("part-*.parquet"))
    assert Path(path).name == cli_part.name
    assert Path(path).read_bytes() == cli_part.read_bytes()


def test_ctrl_c_ends_a_stage_that_writes_files_and_leaves_nothing(tmp_path: Path) -> None:
    out = tmp_path / "big"
    assert interrupt_after(f"stickslip.simulate(realizations=10**8, out={str(out)!r})", 1.5) < 5
    # the stage's own cleanup: no part file, no temporary, no directory it created
    assert not out.exists() or not any(out.iterdir()), list(out.iterdir())
    # and an analysis, in-process too (1.2·10^6 realizations take about 2.4 s to analyse on 2
    # cores: the signal comes well inside it)
    data = tmp_path / "d"
    stickslip.simulate(realizations=1_200_000, out=data)
    assert interrupt_after(f"stickslip.analyze({str(data)!r}, out={str(tmp_path / 'a')!r})", 0.8) < 5
    assert not (tmp_path / "a").exists() and [p.name for p in tmp_path.iterdir()] == ["d"]
    # and the exact law, within an iteration of its solve (resolution 80 takes about a minute)
    assert interrupt_after(f"stickslip.exact_law(out={str(tmp_path / 'law')!r}, resolution=80)", 2.0) < 5
    assert not (tmp_path / "law").exists()


def test_tradeoff_and_sensitivity_return_the_cli_tables(tmp_path: Path) -> None:
    t = stickslip.tradeoff(out=tmp_path / "t", realizations=20)
    assert t.equals(pl.read_parquet(tmp_path / "t" / "tradeoff.parquet")) and "solver" in t.columns
    s = stickslip.sensitivity(set={"model.friction_coefficient": {"dist": "uniform", "low": 0.4, "high": 0.6}}, out=tmp_path / "s", realizations=200)
    assert s.equals(pl.read_parquet(tmp_path / "s" / "sobol.parquet")) and s.height > 0
    with pytest.raises(stickslip.ScenarioError, match="no random key"):
        stickslip.sensitivity(out=tmp_path / "s2", realizations=20)


def test_exact_law_and_predict_return_the_cli_tables(tmp_path: Path) -> None:
    law = stickslip.exact_law(out=tmp_path / "law", resolution=16, tail_times=[0.75])
    m = law.moments
    assert m.equals(pl.read_parquet(tmp_path / "law" / "moments.parquet")) and m.height == 24
    assert set(law) >= {"stationary", "moments", "convergence", "density", "stick_survival", "survival"}
    d = law["survival"]
    assert set(d["index"]) == set(range(1, 7)) and d.filter(pl.col("t") == 0.75).height == 6
    p = stickslip.predict((0.5, 0.0, 1.0), resolution=16, futures=2000)
    assert set(p["method"]) == {"exact", "monte_carlo"} and "time_to_stick" in set(p["variable"])
    with pytest.raises(ValueError, match="not a state of this belt"):
        stickslip.predict((0.5, 0.0, 2.0))
    # the counts' laws reach the CLI: a window of 15 mean flip times is refused before any solve
    with pytest.raises(ValueError, match="--counts"):
        stickslip.exact_law(out=tmp_path / "law2", resolution=16, counts=8, set={"run.duration": 3.0})
    assert not (tmp_path / "law2").exists()
    # and the densities': a point initial condition (T_1 has a point mass) is refused
    point = {"initial_conditions.position": [0.5, 0.5], "initial_conditions.velocity": [0.0, 0.0]}
    with pytest.raises(ValueError, match="--densities: the initial condition is a point"):
        stickslip.exact_law(out=tmp_path / "law3", resolution=16, densities=8, set=point)
    assert not (tmp_path / "law3").exists()


def test_a_path_with_equals_and_brackets_is_read_as_a_path(tmp_path: Path) -> None:
    # named like the tool's own sweep cells: `=` and `[` are no sign of TOML text
    cell = tmp_path / "hive[0]" / "mass=1"
    cell.mkdir(parents=True)
    (cell / "scene.toml").write_text("[model]\ndamping = 0.5\n")
    by_dict = pl.DataFrame(stickslip.simulate({"model": {"damping": 0.5}}, realizations=20))
    assert by_dict.height == 20
    assert pl.DataFrame(stickslip.simulate(str(cell / "scene.toml"), realizations=20)).equals(by_dict)
    assert pl.DataFrame(stickslip.simulate(cell / "scene.toml", realizations=20)).equals(by_dict)
    # through the command line too (out=)
    stickslip.simulate(str(cell / "scene.toml"), realizations=20, out=tmp_path / "d")
    assert pl.read_parquet(tmp_path / "d").sort("realization").equals(by_dict)
    # a missing one is a missing file, not bad TOML
    with pytest.raises(ValueError, match="nope=1"):
        stickslip.simulate(str(tmp_path / "[x]" / "nope=1.toml"), realizations=20)


def test_toml_text_is_given_as_toml_and_a_str_with_a_newline_is_refused(tmp_path: Path) -> None:
    text = stickslip.Toml("[model]\ndamping = 0.5\n")
    assert "Toml" in stickslip.__all__ and text.text == "[model]\ndamping = 0.5\n"
    by_dict = pl.DataFrame(stickslip.simulate({"model": {"damping": 0.5}}, realizations=20))
    assert pl.DataFrame(stickslip.simulate(text, realizations=20)).equals(by_dict)
    stickslip.simulate(text, realizations=20, out=tmp_path / "d")
    assert pl.read_parquet(tmp_path / "d").sort("realization").equals(by_dict)
    # a str is a path, whatever it holds; one with a newline gets the hint
    with pytest.raises(ValueError, match=r"taken as a path.*stickslip\.Toml\(text\)"):
        stickslip.simulate("[model]\ndamping = 0.5\n", realizations=20)
    with pytest.raises(ValueError, match=r"stickslip\.Toml\(text\)"):
        stickslip.exact_law("[model]\ndamping = 0.5\n", out=tmp_path / "law", resolution=16)
    assert not (tmp_path / "law").exists()


def test_numpy_numbers_in_set_are_the_python_numbers() -> None:
    np = pytest.importorskip("numpy")
    by_numpy = pl.DataFrame(stickslip.simulate(set={"model.damping": np.float64(0.5), "run.realizations": np.int64(20)}))
    by_python = pl.DataFrame(stickslip.simulate(set={"model.damping": 0.5, "run.realizations": 20}))
    assert by_numpy.height == 20 and by_numpy.equals(by_python)
    # numpy integers as arguments, numpy arrays as lists, numpy booleans as booleans
    assert pl.DataFrame(stickslip.simulate(set={"model.damping": np.float32(0.5)}, realizations=np.int64(20), seed=np.uint64(1))).height == 20
    assert stickslip._args.sets({"model.damping": np.array([0.0, 0.5]), "a.b": np.bool_(True), "a.c": np.int32(-3)}) == [
        "model.damping=[0.0, 0.5]",
        "a.b=true",
        "a.c=-3",
    ]


def test_a_value_that_is_not_finite_is_refused_naming_its_key() -> None:
    with pytest.raises(ValueError, match="set: model.damping = nan: must be a finite number"):
        stickslip.simulate(set={"model.damping": float("nan")}, realizations=20)
    np = pytest.importorskip("numpy")
    with pytest.raises(ValueError, match="set: model.damping = inf: must be a finite number"):
        stickslip.simulate(set={"model.damping": np.float64("inf")}, realizations=20)
    with pytest.raises(ValueError, match="model.damping = -inf"):
        stickslip.simulate(set={"model.damping": [0.0, -np.inf]}, realizations=20)
    with pytest.raises(ValueError, match="scenario: model.damping = nan"):
        stickslip.simulate({"model": {"damping": np.nan}}, realizations=20)
    with pytest.raises(ValueError, match="set: model.damping = .*not a scenario value"):
        stickslip.simulate(set={"model.damping": object()}, realizations=20)


def test_bad_integer_arguments_raise_value_error_naming_them(tmp_path: Path) -> None:
    # checked before the extension or the command line sees them (no OverflowError)
    with pytest.raises(ValueError, match="seed = -1: must be an integer between 0 and 9223372036854775807"):
        stickslip.simulate(seed=-1, realizations=20)
    with pytest.raises(ValueError, match="seed = 9223372036854775808"):
        stickslip.simulate(seed=2**63, realizations=20)
    with pytest.raises(ValueError, match="realizations = -5: must be an integer"):
        stickslip.simulate(realizations=-5)
    with pytest.raises(ValueError, match="realizations = 2.5"):
        stickslip.simulate(realizations=2.5)
    with pytest.raises(ValueError, match="threads = 0"):
        stickslip.simulate(realizations=20, threads=0)
    with pytest.raises(ValueError, match="seed = True"):
        stickslip.simulate(realizations=20, seed=True)
    with pytest.raises(ValueError, match="seed = -1"):
        stickslip.simulate(realizations=20, seed=-1, out=tmp_path / "d")
    assert not (tmp_path / "d").exists()
    with pytest.raises(ValueError, match="realizations = -5"):
        stickslip.tradeoff(out=tmp_path / "t", realizations=-5)
    with pytest.raises(ValueError, match="realizations = 0"):
        stickslip.sensitivity(out=tmp_path / "s", realizations=0)
    with pytest.raises(ValueError, match="resolution = 0"):
        stickslip.exact_law(out=tmp_path / "law", resolution=0)
    with pytest.raises(ValueError, match="counts = -1"):
        stickslip.exact_law(out=tmp_path / "law", resolution=16, counts=-1)
    with pytest.raises(ValueError, match="futures = 0"):
        stickslip.predict((0.5, 0.0, 1.0), futures=0)
    with pytest.raises(ValueError, match="seed = -1"):
        stickslip.predict((0.5, 0.0, 1.0), seed=-1)
    assert not (tmp_path / "t").exists() and not (tmp_path / "s").exists() and not (tmp_path / "law").exists()


def test_exact_law_and_predict_refuse_bad_numbers_naming_the_argument(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="tail_times = -1.0") as e:
        stickslip.exact_law(out=tmp_path / "law", resolution=16, tail_times=[-1])
    assert "--help" not in str(e.value)
    with pytest.raises(ValueError, match="tail_times = nan"):
        stickslip.exact_law(out=tmp_path / "law", resolution=16, tail_times=[0.5, float("nan")])
    assert not (tmp_path / "law").exists()
    with pytest.raises(ValueError, match="horizon = -1.0: must be a positive number"):
        stickslip.predict((0.5, 0.0, 1.0), horizon=-1)
    with pytest.raises(ValueError, match="horizon = inf"):
        stickslip.predict((0.5, 0.0, 1.0), horizon=float("inf"))
    with pytest.raises(ValueError, match=r"state = \(nan, 0, 1\): must be three finite numbers"):
        stickslip.predict((float("nan"), 0, 1))
    with pytest.raises(ValueError, match="state = "):
        stickslip.predict((0.5, 0.0))


def test_the_stub_names_every_function_of_the_extension_with_its_parameters() -> None:
    import ast
    import inspect

    from stickslip import _stickslip

    stub = ast.parse((Path(stickslip.__file__).parent / "_stickslip.pyi").read_text())
    stubbed = {f.name: [a.arg for a in f.args.args] for f in stub.body if isinstance(f, ast.FunctionDef)}
    classes = {c.name for c in stub.body if isinstance(c, ast.ClassDef)}
    functions = {n: f for n, f in vars(_stickslip).items() if callable(f) and not isinstance(f, type)}
    assert set(stubbed) == set(functions)
    for name, f in functions.items():
        assert stubbed[name] == list(inspect.signature(f).parameters), name
    assert classes == {n for n, c in vars(_stickslip).items() if isinstance(c, type)}


def test_progress_is_drawn_on_stderr_when_asked(capfd: pytest.CaptureFixture) -> None:
    stickslip.simulate(realizations=20_000, progress=True)
    err = capfd.readouterr().err
    assert "20000/20000" in err or "20000/20000" in err.replace(" ", "")
    stickslip.simulate(realizations=20_000)
    assert capfd.readouterr().err == ""


def test_a_sweep_analysed_from_python_has_its_cells(tmp_path: Path) -> None:
    stickslip.simulate(set={"model.damping": [0.0, 0.5]}, realizations=300, out=tmp_path / "d")
    a = stickslip.analyze(tmp_path / "d", out=tmp_path / "a")
    assert sorted(a.cells) == ["damping=0", "damping=0.5"] and a.summary is None
    assert a.sweep.equals(pl.read_parquet(tmp_path / "a" / "sweep.parquet"))
    cell = a.cells["damping=0.5"]
    assert cell.moments.equals(pl.read_parquet(tmp_path / "a" / "damping=0.5" / "moments.parquet"))
    assert cell.summary is not None and cell.summary.dataset.realizations == 300


def _python_block(text: str, after: str) -> str:
    section = text[text.index(after) :]
    start = section.index("```python") + len("```python")
    return section[start : section.index("```", start)]


def test_the_readme_python_example_prints_what_the_readme_says(tmp_path: Path) -> None:
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    code = _python_block(readme, "## From Python")
    begin, end = "<!-- readme python stdout: begin -->\n```text\n", "\n```\n<!-- readme python stdout: end -->"
    quoted = readme[readme.index(begin) + len(begin) : readme.index(end)]
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.rstrip("\n") == quoted, f"the README's Python block prints:\n{r.stdout}"


def test_the_python_tutorial_runs_as_written(tmp_path: Path) -> None:
    page = (Path(__file__).resolve().parents[2] / "docs" / "src" / "tutorials" / "python.md").read_text()
    code = _python_block(page, "## 3. The API in one screen")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_the_version_is_the_command_lines() -> None:
    r = subprocess.run([sys.executable, "-m", "stickslip._cli", "--version"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["stickslip", stickslip.__version__], r.stdout