#!/usr/bin/env python3
"""Execute a notebook headless and fail on any error (for CI).

    python examples/run_notebook.py examples/paper.ipynb [--timeout 600] [--output EXECUTED.ipynb]

The notebook runs in a fresh kernel of *this* interpreter (sys.executable, whatever kernelspecs are
installed), in a temporary working directory, so nothing is written into the repository; the
notebook file itself is only read. --output writes the executed copy, outputs included. Exit
status 0 and "NAME: executed N cells in S s" on success; otherwise 1 and one line on stderr
naming the failing cell and the error.

Tested with (pin these; Python 3.11):
    nbclient==0.11.0 nbformat==5.11.1 ipykernel==7.4.0 jupyter_client==8.10.0
    (pulled in: ipython==9.18.1 jupyter_core==5.9.1 pyzmq==27.3.0 tornado==6.6.1 traitlets==5.16.1;
    the notebooks also need matplotlib, here 3.11.2)
"""

from __future__ import annotations

import argparse
import atexit
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Dict, Optional

import nbformat
from jupyter_client.kernelspec import KernelSpec, KernelSpecManager
from jupyter_client.manager import AsyncKernelManager
from jupyter_core.utils import run_sync
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError, DeadKernelError


class _ThisPython(KernelSpecManager):
    """Every kernel name resolves to an ipykernel of the running interpreter, so the notebook sees
    the packages of the environment the runner was started from (not those of some user-wide
    ``python3`` kernelspec)."""

    def get_kernel_spec(self, kernel_name: str) -> KernelSpec:
        return KernelSpec(
            argv=[sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            display_name=f"Python {sys.version_info[0]} ({sys.executable})",
            language="python",
        )


def _one_line(text: Any) -> str:
    lines = [line.strip() for line in str(text).splitlines() if line.strip()]
    return lines[0] if lines else "(no message)"


def _first_error(nb: nbformat.NotebookNode) -> Optional[tuple]:
    """(cell index, output) of the first output of type "error"."""
    for index, cell in enumerate(nb.cells):
        for output in cell.get("outputs", []) if cell.cell_type == "code" else []:
            if output.get("output_type") == "error":
                return index, output
    return None


def main(argv: Optional[list] = None) -> int:
    parser = argparse.ArgumentParser(description="Execute a notebook headless and fail on any error.")
    parser.add_argument("notebook", type=Path, help="the .ipynb to execute")
    parser.add_argument("--timeout", type=int, default=600, help="seconds allowed per cell (default 600)")
    parser.add_argument("--output", type=Path, help="also write the executed notebook here")
    args = parser.parse_args(argv)
    name = args.notebook.name

    try:
        nb = nbformat.read(args.notebook, as_version=4)
    except (OSError, ValueError) as e:  # missing file, bad JSON, invalid notebook
        print(f"{name}: cannot read: {_one_line(e)}", file=sys.stderr)
        return 1
    # code cell k of n, by cell index (what a reader counts in the notebook)
    code_number = {i: k for k, i in enumerate((i for i, c in enumerate(nb.cells) if c.cell_type == "code"), start=1)}
    n_code = len(code_number)

    def where(index: Optional[int]) -> str:
        if index is None:
            return "before the first cell"
        return f"code cell {code_number[index]} of {n_code} ({_one_line(nb.cells[index].source)!r})"

    state: Dict[str, Any] = {"cell": None, "executed": 0}

    def on_cell_execute(cell: Any, cell_index: int) -> None:
        state["cell"] = cell_index
        state["executed"] += 1

    failure = None
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="run-notebook-") as cwd:
        km = AsyncKernelManager(kernel_name="python3", kernel_spec_manager=_ThisPython())
        if os.name == "posix":
            # Unix sockets in the temporary directory (an absolute path: the kernel's cwd is not
            # ours): a local kernel needs no TCP port, and ipykernel >= 7 warns that TCP without
            # CurveZMQ keys is unencrypted
            km.transport, km.ip = "ipc", os.path.join(cwd, "kernel")
        client = NotebookClient(
            nb, km=km, timeout=args.timeout, allow_errors=False, resources={"metadata": {"path": cwd}}, on_cell_execute=on_cell_execute
        )
        try:
            client.execute(cleanup_kc=True)  # shut the kernel down at the end, although the km is ours
        except CellExecutionError as e:
            failure = f"{where(state['cell'])}: {e.ename}: {_one_line(e.evalue)}"
        except CellTimeoutError:
            failure = f"{where(state['cell'])}: timed out after {args.timeout} s"
        except DeadKernelError as e:
            failure = f"{where(state['cell'])}: the kernel died ({_one_line(e)})"
        except RuntimeError as e:  # e.g. the kernel did not start: "Kernel didn't respond in 60 seconds"
            failure = f"{where(state['cell'])}: {_one_line(e)}"
        finally:
            atexit.unregister(client._cleanup_kernel)  # registered by nbclient; left behind when the kernel failed to start
            if km.has_kernel:
                run_sync(km.shutdown_kernel)(now=True)
    seconds = time.perf_counter() - start

    if args.output is not None:
        nbformat.write(nb, args.output)

    errored = _first_error(nb)  # an error output nbclient did not raise on (e.g. a "raises-exception" tag)
    if failure is None and errored is not None:
        index, output = errored
        failure = f"{where(index)}: {output.get('ename', 'error')}: {_one_line(output.get('evalue', ''))}"
    if failure is not None:
        print(f"{name}: failed in {failure}", file=sys.stderr)
        return 1
    print(f"{name}: executed {state['executed']} cells in {seconds:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
