#!/usr/bin/env python3
"""The standing mutation check: applies each break of scripts/mutants.toml to the working
tree, one at a time, runs the tests it names, restores the files, and reports survivors.

    python3 scripts/mutants.py                  # every break, after a baseline run
    python3 scripts/mutants.py --only NAME ...  # some of them
    python3 scripts/mutants.py --report FILE    # also write the result as a Markdown table

A break is killed when its test command fails (a test fails or the run passes --timeout); it
survives when the command passes. A break whose text is not in its file (stale) or that does
not build is an error, not a kill. The files are restored after each break, on Ctrl-C and on
SIGTERM; a copy of each edited file waits in target/mutants/backup until then, and a later
run restores it first if a run was killed outright. Files with uncommitted changes are
refused. Exit status: 0 when every break was killed, 1 otherwise.
"""

import argparse
import datetime
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BACKUP = ROOT / "target" / "mutants" / "backup"


MUTANT_KEYS = {"name", "pass", "what", "test", "edit", "issue27"}
EDIT_KEYS = {"file", "from", "to"}


def check_shape(mutants):
    """Refuses a list whose entries are not whole breaks: a `[[mutant]]` header left out
    makes TOML file the next break's keys under the previous edit, where they would
    silently never run (it happened to three breaks)."""
    problems = []
    for m in mutants:
        name = m.get("name", "?")
        if not MUTANT_KEYS >= set(m) or not {"name", "test", "edit"} <= set(m):
            problems.append(f"{name}: keys {sorted(m)}")
        for e in m.get("edit", []):
            if set(e) != EDIT_KEYS:
                problems.append(f"{name}: an edit with keys {sorted(e)} (a [[mutant]] header missing?)")
    names = [m.get("name") for m in mutants]
    problems += [f"{n}: listed twice" for n in sorted({n for n in names if names.count(n) > 1})]
    if problems:
        sys.exit("scripts/mutants.toml is malformed:\n" + "\n".join(problems))


def check_edits_apply(mutants):
    """Refuses a list whose edits no longer apply: each `from` must occur exactly once in its
    file, or the break would be skipped as unappliable (or hit the wrong place) when it runs.
    Merges and renames drift them silently; `scripts/test.sh` runs this (`--check`)."""
    problems = []
    for m in mutants:
        for e in m["edit"]:
            path = ROOT / e["file"]
            if not path.is_file():
                problems.append(f"{m['name']}: {e['file']} does not exist")
                continue
            count = path.read_text().count(e["from"])
            if count != 1:
                problems.append(f"{m['name']}: its edit's text occurs {count} times in {e['file']}")
    if problems:
        sys.exit("scripts/mutants.toml has edits that do not apply:\n" + "\n".join(problems))


def restore_backup():
    """Puts back the files a killed run left mutated."""
    if not BACKUP.exists():
        return
    for saved in BACKUP.rglob("*"):
        if saved.is_file():
            target = ROOT / saved.relative_to(BACKUP)
            shutil.copy2(saved, target)
            print(f"restored {target.relative_to(ROOT)} from an interrupted run")
    shutil.rmtree(BACKUP)


def apply(mutant):
    """Edits the files of one break (after backing them up); returns the originals."""
    originals = {}
    for edit in mutant["edit"]:
        path = ROOT / edit["file"]
        text = originals.get(path) or path.read_text()
        originals.setdefault(path, text)
    for path, text in originals.items():
        saved = BACKUP / path.relative_to(ROOT)
        saved.parent.mkdir(parents=True, exist_ok=True)
        saved.write_text(text)
    edited = dict(originals)
    for edit in mutant["edit"]:
        path = ROOT / edit["file"]
        count = edited[path].count(edit["from"])
        if count != 1:
            raise LookupError(f"{edit['file']}: the text occurs {count} times, not once")
        edited[path] = edited[path].replace(edit["from"], edit["to"])
    for path, text in edited.items():
        path.write_text(text)
    return originals


def restore(originals):
    for path, text in originals.items():
        path.write_text(text)
    shutil.rmtree(BACKUP, ignore_errors=True)


def cargo(args, timeout=None):
    """Runs cargo test with `args`; returns (status, output, seconds), status None on timeout."""
    env = dict(os.environ)
    env.setdefault("XDG_RUNTIME_DIR", "/tmp")
    env["MOTION_SHADOWS_VALIDATION"] = "1"
    start = time.monotonic()
    proc = subprocess.Popen(
        ["cargo", "test", *args],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:
        out, _ = proc.communicate(timeout=timeout)
        status = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
        status = None
    return status, out, time.monotonic() - start


def build_args(test):
    """`cargo test` arguments that only build what `test` runs."""
    args = test.split()
    return (args[: args.index("--")] if "--" in args else args) + ["--no-run"]


def tests_of(mutant):
    """The `cargo test` argument strings of a break (one string or a list, run in order)."""
    test = mutant["test"]
    return [test] if isinstance(test, str) else test


def failed_tests(output):
    return re.findall(r"^test (\S+) \.\.\. FAILED", output, re.MULTILINE)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", default=str(ROOT / "scripts" / "mutants.toml"))
    parser.add_argument("--only", nargs="*", help="names of the breaks to run")
    parser.add_argument("--report", help="write the result as Markdown here")
    parser.add_argument("--timeout", type=int, default=900, help="seconds per test run")
    parser.add_argument("--check", action="store_true",
                        help="only check that the list is well formed and every edit applies once")
    parser.add_argument("--no-baseline", action="store_true",
                        help="skip checking that the unbroken tree passes each test command")
    opts = parser.parse_args()

    # SIGTERM unwinds like Ctrl-C, so the files are restored.
    signal.signal(signal.SIGTERM, lambda *_: (_ for _ in ()).throw(KeyboardInterrupt()))
    if not opts.check:
        # (--check only reads.)
        restore_backup()

    mutants = tomllib.loads(Path(opts.list).read_text())["mutant"]
    check_shape(mutants)
    if opts.check:
        check_edits_apply(mutants)
        print(f"scripts/mutants.toml: {len(mutants)} breaks, each edit applies once")
        return
    if opts.only:
        unknown = set(opts.only) - {m["name"] for m in mutants}
        if unknown:
            sys.exit(f"no such break: {', '.join(sorted(unknown))}")
        mutants = [m for m in mutants if m["name"] in opts.only]
    files = sorted({e["file"] for m in mutants for e in m["edit"]})
    dirty = subprocess.run(["git", "status", "--porcelain", "--", *files], cwd=ROOT,
                           capture_output=True, text=True, check=True).stdout
    if dirty.strip():
        sys.exit(f"uncommitted changes in files the breaks edit:\n{dirty}")

    if not opts.no_baseline:
        for test in sorted({t for m in mutants for t in tests_of(m)}):
            status, out, secs = cargo(test.split(), opts.timeout)
            if status != 0:
                sys.stdout.write(out[-4000:])
                sys.exit(f"the unbroken tree fails `cargo test {test}`: no break can be judged")
            ran = sum(int(n) for n in re.findall(r"test result: ok\. (\d+) passed", out))
            if ran == 0:
                sys.exit(f"`cargo test {test}` runs no test")
            print(f"baseline passes: cargo test {test} ({ran} tests, {secs:.0f} s)")

    results = []
    try:
        for m in mutants:
            print(f"--- {m['name']}: {m['what']}", flush=True)
            try:
                originals = apply(m)
            except LookupError as e:
                results.append((m, "stale", str(e)))
                print(f"    stale: {e}")
                continue
            verdict, detail, secs = "SURVIVED", "all tests passed", 0.0
            try:
                for test in tests_of(m):
                    status, out, _ = cargo(build_args(test))
                    if status != 0:
                        verdict, detail = "unbuildable", out[-300:].strip()
                        print(f"    does not build:\n{out[-2000:]}")
                        break
                    status, out, took = cargo(test.split(), opts.timeout)
                    secs += took
                    if status is None:
                        verdict, detail = "killed", f"timeout after {opts.timeout} s"
                        break
                    if status != 0:
                        names = failed_tests(out)
                        verdict, detail = "killed", ", ".join(names) or "the test run failed"
                        break
            finally:
                restore(originals)
            results.append((m, verdict, detail))
            print(f"    {verdict}: {detail} ({secs:.0f} s)", flush=True)
    except KeyboardInterrupt:
        print("interrupted; the files are restored")
        raise

    survivors = [r for r in results if r[1] != "killed"]
    print(f"\n{len(results) - len(survivors)} of {len(results)} breaks killed")
    for m, verdict, detail in survivors:
        print(f"  {verdict}: {m['name']} ({detail})")
    if opts.report:
        write_report(Path(opts.report), results)
    return 0 if not survivors else 1


def write_report(path, results):
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                          capture_output=True, text=True).stdout.strip()
    lines = [
        f"Run on {datetime.date.today().isoformat()} at commit `{head}` with "
        f"`python3 {' '.join(sys.argv)}` (lavapipe, validation on): "
        f"{sum(r[1] == 'killed' for r in results)} of {len(results)} breaks killed.",
        "",
        "| Break | Pass | What it breaks | Result | Failing tests |",
        "|---|---|---|---|---|",
    ]
    for m, verdict, detail in results:
        tag = " (issue 27)" if m.get("issue27") else ""
        detail = detail.replace("|", "\\|")
        lines.append(f"| `{m['name']}`{tag} | {m['pass']} | {m['what']} | {verdict} | {detail} |")
    path.write_text("\n".join(lines) + "\n")
    print(f"report: {path}")


if __name__ == "__main__":
    sys.exit(main())
