#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The CAD corpus benchmark: real-world STEP/IGES models through `python3 -m ctsplines convert`
with its default options, measured against the conversion's promises (issue 11, points 2, 4, 6).

The models come from Debian packages at run time (never committed: they carry their packages'
licences): `apt-get download kicad-packages3d occt-misc gmsh-doc` into CACHE/debs, and
`dpkg --fsys-tarfile PKG.deb | tar -x` of just the files needed into CACHE/models. The sample is
seeded and stratified: --sample KiCad models per face-count stratum (5-60, 60-300, 300-2000 faces,
counted as ADVANCED_FACE entities of the STEP text, spread over the *.3dshapes folders), plus
every STEP/IGES file of occt-misc and gmsh-doc. Per model, ctsplines_cad_facts says what OCCT
sees (faces, closed, free/non-manifold/tangent edges, its plain read time) and the CLI converts
it (`--summary-json`); one line per model, then the pass rate per criterion for the closed models
and for all. --out writes a TSV that --compare reads back.

    nice python3 Testing/Benchmarks/cad_corpus.py --build build --cache ~/.cache/ctsplines-corpus \\
        --sample 70 --out before.tsv
    python3 Testing/Benchmarks/cad_corpus.py --compare before.tsv after.tsv

--case NAME --cases FILE runs one case of the ctest list (cad_corpus_cases.txt; label
cad-corpus), --fetch-cases fetches that list's models (exit 77 when the download fails).
Standard library only; the conversion runs in /usr/bin/python3 on the build tree's package.
"""
import argparse
import concurrent.futures
import gzip
import hashlib
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

PACKAGES = ("kicad-packages3d", "occt-misc", "gmsh-doc")
KICAD_DIR = "usr/share/kicad/3dmodels"
OCCT_DIR = "usr/share/opencascade/data"
GMSH_DIR = "usr/share/doc/gmsh-doc"
STRATA = ((5, 60), (60, 300), (300, 2000))
CAD_EXTENSIONS = (".step", ".stp", ".iges", ".igs")
SKIP = 77  # ctest's SKIP_RETURN_CODE

# --- criteria (the one implementation: the corpus run and the ctest cases) -------------------

# Name, what it asserts (printed in the table).
CRITERIA = (
    ("converts", "converts, or exits non-zero with an `error:` line (no signal, timeout, "
     "traceback)"),
    ("free_edges", "0 free edges"),
    ("non_manifold", "no non-manifold edge beyond the B-rep's (spans of B-rep edges of 3+ faces)"),
    ("c0_gap", "C0 gap exactly 0"),
    ("deviation", "max deviation <= tolerance (<= 2x the model's own edge gap where larger)"),
    ("g1", "max G1 angle over tangent interfaces <= 0.1 degrees"),
    ("g1_flip", "no flipped normal: G1 angle over tangent interfaces <= 90 degrees"),
    ("normal_deviation", "normal deviation reported (max and RMS)"),
    ("time", "CLI wall time <= 1.5 x OCCT read time + 1 s"),
)
CRITERION_NAMES = tuple(name for name, _ in CRITERIA)
G1_MAX_DEGREES = 0.1


def _number(summary, key):
    """A figure of the summary, None when not reported (missing key, null)."""
    value = summary.get(key)
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def evaluate(facts, run):
    """Criterion name -> (passed, figure) for one model. facts: ctsplines_cad_facts' dict (may
    hold "error"); run: exit_status, signal, timed_out, traceback, error_line, wall, summary
    (the --summary-json dict or None). passed is None when the criterion cannot be judged."""
    s = run.get("summary") or {}
    converted = run["exit_status"] == 0 and bool(s) and s.get("error") is None
    out = {}
    if run.get("timed_out"):
        out["converts"] = (False, f"timeout after {run['wall']:.0f} s")
    elif run.get("signal"):
        out["converts"] = (False, f"killed by signal {run['signal']}")
    elif run.get("traceback"):
        out["converts"] = (False, "traceback")
    elif converted:
        out["converts"] = (True, "converted")
    else:
        out["converts"] = (bool(run.get("error_line")) and run["exit_status"] != 0,
                           f"exit {run['exit_status']}: "
                           + (run.get("error_line") or "no error line: "
                              + run.get("stderr_tail", "")[-150:]))

    def judge(name, key, test, text):
        value = _number(s, key)
        if not converted:
            out[name] = (False, "not converted")
        elif value is None:
            out[name] = (False, f"{key} not reported")
        else:
            out[name] = (bool(test(value)), text(value))

    judge("free_edges", "free_edges", lambda v: v == 0, lambda v: f"free edges {v}")
    brep_nm = facts.get("non_manifold_edges") or 0
    judge("non_manifold", "extra_non_manifold_edges", lambda v: v == 0,
          lambda v: f"non-manifold edges {s.get('non_manifold_edges')}, {v} not on the B-rep's "
                    f"{brep_nm}")
    judge("c0_gap", "c0_gap", lambda v: v == 0, lambda v: f"C0 gap {v:.3g}")
    tol = (s.get("options") or {}).get("tolerance", 1e-4)
    gap, diagonal = _number(s, "edge_gap"), _number(s, "diagonal")
    bound = max(tol, 2 * gap / diagonal) if gap and diagonal else tol
    judge("deviation", "max_deviation", lambda v: v <= bound * (1 + 1e-9),
          lambda v: f"deviation {v:.3g} (bound {bound:.3g})")
    tangent = _number(s, "tangent_edges")
    if converted and tangent == 0:
        out["g1"] = out["g1_flip"] = (True, "no tangent interface")
    else:
        judge("g1", "g1_angle_tangent", lambda v: v <= G1_MAX_DEGREES,
              lambda v: f"G1 {v:.3g} deg over {tangent} tangent edges")
        judge("g1_flip", "g1_angle_tangent", lambda v: v <= 90, lambda v: f"G1 {v:.3g} deg")
    if not converted:
        out["normal_deviation"] = (False, "not converted")
    else:
        nmax, nrms = _number(s, "max_normal_deviation"), _number(s, "rms_normal_deviation")
        out["normal_deviation"] = ((nmax is not None and nrms is not None),
                                   "not reported" if nmax is None else
                                   f"normal deviation max {nmax:.3g} deg, RMS {nrms}")
    read = facts.get("read_time")
    if read is None:
        out["time"] = (None, "no OCCT read time")
    else:
        limit = 1.5 * read + 1
        out["time"] = (run["wall"] <= limit, f"wall {run['wall']:.2f} s (limit {limit:.2f} s)")
    return out


def overall(results):
    """All criteria judged pass (None counts as not passed)."""
    return all(results[name][0] for name in CRITERION_NAMES if name in results)


# --- running one model ------------------------------------------------------------------------

def run_process(command, timeout, env=None, cwd=None):
    """(returncode, stdout, stderr, wall seconds, timed_out); the whole process group is
    killed on timeout (the CLI forks OpenCASCADE's reading child)."""
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                            cwd=cwd, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        timed_out = True
    wall = time.perf_counter() - start
    return proc.returncode, out.decode(errors="replace"), err.decode(errors="replace"), wall, \
        timed_out


def model_facts(facts_program, model, timeout):
    """ctsplines_cad_facts' JSON line for the model ({"error": ...} when it has none)."""
    try:
        code, out, err, _, timed_out = run_process([facts_program, model], timeout)
    except OSError as e:
        return {"error": f"cannot run {facts_program}: {e}"}
    for line in reversed(out.splitlines()):
        if line.startswith('{"model"'):
            return json.loads(line)
    reason = "timeout" if timed_out else f"exit {code}: {err.strip()[-200:]}"
    return {"error": f"ctsplines_cad_facts: {reason}"}


def convert(model, python_path, timeout, work):
    """Runs the CLI with default options; the run's dict for evaluate(), plus stdout's stage
    line."""
    out_vtm = os.path.join(work, "out.vtm")
    summary_path = os.path.join(work, "summary.json")
    env = dict(os.environ, PYTHONPATH=python_path, PYTHONDONTWRITEBYTECODE="1")
    command = ["/usr/bin/python3", "-m", "ctsplines", "convert", model, "-o", out_vtm,
               "--summary-json", summary_path, "--no-progress"]
    code, out, err, wall, timed_out = run_process(command, timeout, env=env, cwd=work)
    summary = None
    if os.path.exists(summary_path):
        with open(summary_path, encoding="utf-8") as f:
            summary = json.load(f)
    lines = err.splitlines()
    first = next((i for i, line in enumerate(lines) if line.startswith("error:")), None)
    error = ""
    if first is not None:  # the error line and its indented details
        end = next((i for i in range(first + 1, len(lines)) if not lines[i].startswith(" ")),
                   len(lines))
        error = " | ".join(line.strip() for line in lines[first:end])
    stages = next((line for line in out.splitlines() if line.startswith("time [s]:")), "")
    return {"exit_status": code, "signal": -code if code is not None and code < 0 else 0,
            "timed_out": timed_out, "traceback": "Traceback (most recent call last)" in err,
            "error_line": error, "wall": wall, "summary": summary,
            "stages": stages[len("time [s]: "):], "stderr_tail": err.strip()[-300:]}


def measure(model, facts_program, python_path, timeout):
    """facts, run and criteria of one model."""
    facts = model_facts(facts_program, model, timeout)
    with tempfile.TemporaryDirectory(prefix="ctsplines-corpus-") as work:
        run = convert(model, python_path, timeout, work)
    return facts, run, evaluate(facts, run)


# --- models: fetching, face counts, the sample ------------------------------------------------

def fetch_debs(cache, packages=PACKAGES):
    """CACHE/debs/PKG_*.deb per package (apt-get download when missing); None on failure."""
    debs = os.path.join(cache, "debs")
    os.makedirs(debs, exist_ok=True)
    found = {}
    for package in packages:
        names = sorted(n for n in os.listdir(debs) if n.startswith(package + "_")
                       and n.endswith(".deb"))
        if not names:
            r = subprocess.run(["apt-get", "download", package], cwd=debs,
                               capture_output=True, text=True)
            names = sorted(n for n in os.listdir(debs) if n.startswith(package + "_")
                           and n.endswith(".deb"))
            if r.returncode != 0 or not names:
                print(f"cannot download {package}: {r.stderr.strip()[-200:]}", file=sys.stderr)
                return None
        found[package] = os.path.join(debs, names[-1])
    return found


def deb_members(deb):
    """The file names of a .deb's data (tar member names without './')."""
    tar = subprocess.run(f"dpkg --fsys-tarfile '{deb}' | tar -t", shell=True,
                         capture_output=True, text=True, check=True)
    return [n[2:] if n.startswith("./") else n for n in tar.stdout.splitlines()
            if not n.endswith("/")]


def extract(cache, deb, paths):
    """Extracts the given paths of the deb into CACHE/models (those not there yet)."""
    root = os.path.join(cache, "models")
    missing = [p for p in paths if not os.path.exists(os.path.join(root, p))]
    if not missing:
        return
    os.makedirs(root, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", suffix=".list") as names:
        names.write("".join(f"./{p}\n" for p in missing))
        names.flush()
        subprocess.run(f"dpkg --fsys-tarfile '{deb}' | tar -x -C '{root}' -T '{names.name}'",
                       shell=True, check=True)


_FACE = re.compile(rb"\bADVANCED_FACE\s*\(|\bFACE_SURFACE\s*\(")


def count_faces(data):
    return len(_FACE.findall(data))


def kicad_index(cache, deb):
    """KiCad model path (relative to CACHE/models) -> face count, cached in
    CACHE/kicad_faces.tsv; counted from the extracted files when the package is extracted
    (CACHE/models/EXTRACTED), else streamed from the deb without extracting."""
    index_path = os.path.join(cache, "kicad_faces.tsv")
    if os.path.exists(index_path):
        with open(index_path, encoding="utf-8") as f:
            return {path: int(n) for path, n in (line.rstrip("\n").split("\t") for line in f)}
    index = {}
    root = os.path.join(cache, "models")
    if os.path.exists(os.path.join(root, "EXTRACTED")):
        for folder, _, files in os.walk(os.path.join(root, KICAD_DIR)):
            for name in files:
                if name.lower().endswith((".step", ".stp")):
                    path = os.path.join(folder, name)
                    with open(path, "rb") as f:
                        index[os.path.relpath(path, root)] = count_faces(f.read())
    else:
        import tarfile

        proc = subprocess.Popen(["dpkg", "--fsys-tarfile", deb], stdout=subprocess.PIPE)
        with tarfile.open(fileobj=proc.stdout, mode="r|") as tar:
            for member in tar:
                name = member.name[2:] if member.name.startswith("./") else member.name
                if member.isfile() and name.lower().endswith((".step", ".stp")):
                    index[name] = count_faces(tar.extractfile(member).read())
        proc.wait()
    with open(index_path + ".tmp", "w", encoding="utf-8") as f:
        f.writelines(f"{path}\t{n}\n" for path, n in sorted(index.items()))
    os.replace(index_path + ".tmp", index_path)
    return index


def stratified_sample(index, per_stratum, seed):
    """Per stratum, models drawn round-robin over the *.3dshapes folders (each folder's models
    shuffled, the folders' order shuffled), so that the sample spreads over the kinds of part."""
    rng = random.Random(seed)
    picked = []
    for lo, hi in STRATA:
        folders = {}
        for path, n in sorted(index.items()):
            if lo <= n < hi:
                folders.setdefault(os.path.dirname(path), []).append(path)
        order = sorted(folders)
        rng.shuffle(order)
        for folder in order:
            rng.shuffle(folders[folder])
        chosen = []
        while len(chosen) < per_stratum and any(folders[f] for f in order):
            for folder in order:
                if folders[folder] and len(chosen) < per_stratum:
                    chosen.append(folders[folder].pop())
        picked += [(path, f"kicad {lo}-{hi}") for path in chosen]
    return picked


def unpack_gz(cache, path):
    """CACHE/unpacked/NAME for a .gz model (unpacked once)."""
    target = os.path.join(cache, "unpacked", os.path.basename(path)[:-3])
    if not os.path.exists(target):
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with gzip.open(os.path.join(cache, "models", path), "rb") as src, \
                open(target + ".tmp", "wb") as dst:
            shutil.copyfileobj(src, dst)
        os.replace(target + ".tmp", target)
    return target


def other_models(cache, debs):
    """Every STEP/IGES file of occt-misc and gmsh-doc (gmsh-doc's are .gz; identical contents
    once), as (absolute path, set)."""
    models, seen = [], set()
    for package, folder in (("occt-misc", OCCT_DIR), ("gmsh-doc", GMSH_DIR)):
        members = [m for m in deb_members(debs[package]) if m.startswith(folder)
                   and m.lower().removesuffix(".gz").endswith(CAD_EXTENSIONS)]
        extract(cache, debs[package], members)
        for member in sorted(members):
            path = (unpack_gz(cache, member) if member.endswith(".gz")
                    else os.path.join(cache, "models", member))
            with open(path, "rb") as f:
                digest = hashlib.sha256(f.read()).hexdigest()
            if digest not in seen:
                seen.add(digest)
                models.append((path, package))
    return models


def corpus(cache, per_stratum, seed):
    debs = fetch_debs(cache)
    if debs is None:
        sys.exit("the corpus packages cannot be downloaded")
    index = kicad_index(cache, debs["kicad-packages3d"])
    sample = stratified_sample(index, per_stratum, seed)
    extract(cache, debs["kicad-packages3d"], [path for path, _ in sample])
    kicad = [(os.path.join(cache, "models", path), kind) for path, kind in sample]
    return kicad + other_models(cache, debs)


# --- the table ---------------------------------------------------------------------------------

COLUMNS = ("model", "set", "faces", "closed", "brep_free", "brep_non_manifold", "brep_degenerated",
           "brep_tangent", "read_time", "exit", "wall", "overall") + CRITERION_NAMES + (
    "figures", "stages", "error")


def row(model, kind, facts, run, results):
    r = {"model": model, "set": kind, "faces": facts.get("faces", ""),
         "closed": {True: "yes", False: "no"}.get(facts.get("closed"), "?"),
         "brep_free": facts.get("free_edges", ""),
         "brep_non_manifold": facts.get("non_manifold_edges", ""),
         "brep_degenerated": facts.get("degenerated_edges", ""),
         "brep_tangent": facts.get("tangent_edges", ""),
         "read_time": f"{facts['read_time']:.3f}" if "read_time" in facts else "",
         "exit": "timeout" if run["timed_out"] else run["exit_status"],
         "wall": f"{run['wall']:.3f}", "overall": "pass" if overall(results) else "fail",
         "figures": "; ".join(f"{n}: {results[n][1]}" for n in CRITERION_NAMES),
         "stages": run.get("stages", ""),
         "error": (run.get("error_line") or facts.get("error") or "")[:800]}
    for name in CRITERION_NAMES:
        r[name] = {True: "pass", False: "fail", None: "n/a"}[results[name][0]]
    return {k: str(v).replace("\t", " ").replace("\n", " ") for k, v in r.items()}


def read_table(path):
    with open(path, encoding="utf-8") as f:
        header = f.readline().rstrip("\n").split("\t")
        return [dict(zip(header, line.rstrip("\n").split("\t"))) for line in f if line.strip()]


# Aggregates of the table: the geometric guarantees of point 2 (all but the normal deviation),
# point 2 and 4 whole (all but time), and every criterion.
AGGREGATES = (("geometry", CRITERION_NAMES[:-2]), ("guarantees", CRITERION_NAMES[:-1]),
              ("overall", CRITERION_NAMES))


def pass_rates(rows):
    """Criterion or aggregate -> (closed passed, closed judged, all passed, all judged)."""
    rows = [dict(r, **{name: "pass" if all(r.get(c) == "pass" for c in names) else "fail"
                       for name, names in AGGREGATES}) for r in rows]
    rates = {}
    for name in CRITERION_NAMES + tuple(name for name, _ in AGGREGATES):
        cells = [(r["closed"] == "yes", r[name]) for r in rows if r.get(name) in ("pass", "fail")]
        rates[name] = (sum(c and v == "pass" for c, v in cells), sum(c for c, _ in cells),
                       sum(v == "pass" for _, v in cells), len(cells))
    return rates


def _percent(passed, total):
    return f"{passed}/{total} ({100 * passed / total:.0f} %)" if total else "-"


def print_rates(rows, title):
    print(f"\n{title}: {len(rows)} models, {sum(r['closed'] == 'yes' for r in rows)} closed")
    print(f"{'criterion':<18} {'closed models':>18} {'all models':>18}")
    for name, (cp, cn, ap, an) in pass_rates(rows).items():
        print(f"{name:<18} {_percent(cp, cn):>18} {_percent(ap, an):>18}")


def compare(old_path, new_path):
    old, new = pass_rates(read_table(old_path)), pass_rates(read_table(new_path))
    print(f"{'criterion':<18} {'closed before':>16} {'closed after':>16} {'all before':>16} "
          f"{'all after':>16}")
    for name in old:
        o, n = old.get(name, (0, 0, 0, 0)), new.get(name, (0, 0, 0, 0))
        print(f"{name:<18} {_percent(o[0], o[1]):>16} {_percent(n[0], n[1]):>16} "
              f"{_percent(o[2], o[3]):>16} {_percent(n[2], n[3]):>16}")


def print_slowest(rows, count=5):
    print(f"\nslowest {count} (CLI wall time; stages in seconds; other: Python, VTK's import, "
          "writing):")
    for r in sorted(rows, key=lambda r: -float(r["wall"] or 0))[:count]:
        total = re.search(r"total (\S+)", r["stages"])
        other = f"; other {float(r['wall']) - float(total.group(1)):.3f}" if total else ""
        print(f"  {float(r['wall']):8.2f} s  {r['faces']:>5} faces  {r['model']}\n"
              f"            {(r['stages'] + other) or r['error']}")


def write_failures(rows, path):
    """Markdown: per failing criterion, the models (path, faces, figure), worst first where
    the figure is a number."""
    def figure(r, name):
        return dict(f.split(": ", 1) for f in r["figures"].split("; ") if ": " in f).get(name, "")

    def size(text):
        numbers = re.findall(r"(?:^|\s)([-+]?\d+\.?\d*(?:e[-+]?\d+)?)", text)
        return -float(numbers[0]) if numbers else 0.0

    with open(path, "w", encoding="utf-8") as f:
        f.write(f"# CAD corpus failures ({len(rows)} models; cad_corpus.py)\n\n")
        errors = [r for r in rows if r["exit"] != "0"]
        f.write(f"## did not convert ({len(errors)}; their other criteria fail as not "
                "converted and are not listed below)\n\n")
        for r in errors:
            f.write(f"- `{r['model']}` ({r['faces']} faces, closed {r['closed']}): exit "
                    f"{r['exit']}: {r['error'] or figure(r, 'converts')}\n")
        f.write("\n")
        for name, text in CRITERIA:
            failed = sorted((r for r in rows if r.get(name) == "fail" and
                             (r["exit"] == "0" or name == "converts")),
                            key=lambda r: (r["closed"] != "yes", size(figure(r, name))))
            f.write(f"## {name}: {text} ({len(failed)} fail)\n\n")
            shown = failed if len(failed) <= 50 else failed[:20]  # a criterion failing everywhere
            for r in shown:
                f.write(f"- `{r['model']}` ({r['faces']} faces, closed {r['closed']}): "
                        f"{figure(r, name)}\n")
            if len(shown) < len(failed):
                f.write(f"- and {len(failed) - len(shown)} more (the results table)\n")
            f.write("\n")


def model_line(i, total, r, results):
    failed = ", ".join(f"{n}: {results[n][1]}" for n in CRITERION_NAMES
                       if results[n][0] is False)
    return (f"[{i}/{total}] {r['overall'].upper()} {r['model']} ({r['set']}, {r['faces']} faces, "
            f"closed {r['closed']}, wall {r['wall']} s, read {r['read_time'] or '?'} s)"
            + (f": {failed}" if failed else ""))


def run_corpus(models, args):
    done = {}
    if args.resume and args.out and os.path.exists(args.out):
        done = {r["model"]: r for r in read_table(args.out)}
    rows = [done[m] for m, _ in models if m in done]
    todo = [(m, kind) for m, kind in models if m not in done]
    out = None
    if args.out:
        out = open(args.out, "a" if done else "w", encoding="utf-8")
        if not done:
            out.write("\t".join(COLUMNS) + "\n")
    lock = threading.Lock()

    def one(item):
        model, kind = item
        facts, run, results = measure(model, args.facts, args.pythonpath, args.timeout)
        r = row(model, kind, facts, run, results)
        with lock:
            rows.append(r)
            print(model_line(len(rows), len(models), r, results), flush=True)
            if out:
                out.write("\t".join(r[c] for c in COLUMNS) + "\n")
                out.flush()

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for future in [pool.submit(one, item) for item in todo]:
            future.result()
    if out:
        out.close()
    return rows


# --- ctest cases ------------------------------------------------------------------------------

def read_cases(path):
    """name -> {package, member, criteria, xfail, skip}: the lines `NAME PACKAGE MEMBER
    CRITERIA XFAIL` of the cases file (# comments; CRITERIA: all, guarantees (all but time) or
    a comma list; XFAIL: -, skip or the comma list of criteria expected to fail for now)."""
    entries = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            fields = line.split("#", 1)[0].split()
            if fields and line[0].isspace() and entries:  # a continuation line
                entries[-1] += fields
            elif fields:
                entries.append(fields)
    cases = {}
    for fields in entries:
        if len(fields) != 5:
            raise ValueError(f"{path}: {' '.join(fields)}: not NAME PACKAGE MEMBER CRITERIA "
                             "XFAIL")
        name, package, member, criteria, xfail = fields
        names = {"all": CRITERION_NAMES, "guarantees": CRITERION_NAMES[:-1]}.get(
            criteria, tuple(criteria.split(",")))
        expected = () if xfail in ("-", "skip") else tuple(xfail.split(","))
        unknown = set(names + expected) - set(CRITERION_NAMES)
        if unknown:
            raise ValueError(f"{path}: {name}: unknown criteria {', '.join(sorted(unknown))}")
        cases[name] = {"package": package, "member": member, "criteria": names,
                       "xfail": expected, "skip": xfail == "skip"}
    return cases


def case_model(cache, case):
    path = os.path.join(cache, "models", case["member"])
    return unpack_gz(cache, case["member"]) if path.endswith(".gz") else path


def fetch_cases(cases, cache):
    """Downloads the packages of the cases and extracts just their models; 77 when the download
    fails (no network: the cases skip)."""
    packages = sorted({c["package"] for c in cases.values()})
    debs = fetch_debs(cache, packages)
    if debs is None:
        return SKIP
    for package in packages:
        extract(cache, debs[package], [c["member"] for c in cases.values()
                                       if c["package"] == package])
    for case in cases.values():
        case_model(cache, case)
    print(f"{len(cases)} models in {os.path.join(cache, 'models')}")
    return 0


def run_case(name, cases, args):
    """0 when every asserted criterion not expected to fail holds; 1 otherwise; 77 (skip) when
    the model is missing or the case is marked skip."""
    case = cases[name]
    model = case_model(args.cache, case)
    if case["skip"]:
        print(f"{name}: marked skip in the cases file")
        return SKIP
    if not os.path.exists(model):
        print(f"{name}: {model} is missing (not fetched)")
        return SKIP
    facts, run, results = measure(model, args.facts, args.pythonpath, args.timeout)
    print(f"{name}: {model} ({facts.get('faces', '?')} faces, closed {facts.get('closed')})")
    if run["stages"]:
        print(f"  time [s]: {run['stages']}")
    failures, now_passing = [], []
    for criterion in case["criteria"]:
        passed, figure = results[criterion]
        expected = criterion in case["xfail"]
        tag = ("pass" if passed else "FAIL") + (" (expected to fail for now)" if expected else "")
        print(f"  {criterion:<17} {tag}: {figure}")
        if passed is False and not expected:
            failures.append(criterion)
        if passed and expected:
            now_passing.append(criterion)
    if now_passing:
        print(f"  now passing, remove from the case's xfail: {', '.join(now_passing)}")
    if failures:
        print(f"  failed: {', '.join(failures)}\n  {run['stderr_tail']}")
    return 1 if failures else 0


# --- command line -----------------------------------------------------------------------------

def find_build_files(args):
    """Defaults of --facts and --pythonpath from --build."""
    if args.facts is None:
        for folder, _, files in os.walk(args.build):
            if "ctsplines_cad_facts" in files:
                args.facts = os.path.join(folder, "ctsplines_cad_facts")
                break
    if args.pythonpath is None:
        lib = os.path.join(args.build, "lib")
        for folder, dirs, files in os.walk(lib):
            if os.path.basename(folder) == "ctsplines" and "__init__.py" in files:
                args.pythonpath = os.path.dirname(folder)
                break
    if not args.facts or not args.pythonpath:
        sys.exit(f"no ctsplines_cad_facts or ctsplines package in {args.build} "
                 "(build it, or give --facts and --pythonpath)")
    # The CLI runs in a temporary folder: a relative path would find an installed ctsplines.
    args.facts, args.pythonpath = os.path.abspath(args.facts), os.path.abspath(args.pythonpath)


def parse_args(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build", default=os.path.join(here, "..", "..", "build"),
                   help="the build tree (default: the source tree's build/)")
    p.add_argument("--facts", help="ctsplines_cad_facts (default: found in --build)")
    p.add_argument("--pythonpath", help="folder of the ctsplines package (default: in --build)")
    p.add_argument("--cache", default=os.path.expanduser("~/.cache/ctsplines-corpus"),
                   help="CACHE/debs: the packages; CACHE/models: the extracted files "
                   "(default %(default)s)")
    p.add_argument("--sample", type=int, default=70, help="KiCad models per face-count stratum "
                   "(default %(default)s)")
    p.add_argument("--seed", type=int, default=11, help="seed of the sample (default %(default)s)")
    p.add_argument("--jobs", type=int, default=1, help="models converted at once (default 1)")
    p.add_argument("--timeout", type=float, default=600,
                   help="seconds per model and program (default %(default)g)")
    p.add_argument("--out", help="write the results as TSV (one row per model)")
    p.add_argument("--resume", action="store_true",
                   help="keep the models already in --out and run the others")
    p.add_argument("--models", nargs="+", metavar="MODEL", help="run these files only")
    p.add_argument("--list", action="store_true", help="print the sample and exit")
    p.add_argument("--table", metavar="TSV",
                   help="summarise a results TSV (pass rates, slowest) instead of running")
    p.add_argument("--failures", metavar="MD",
                   help="write the failing models per criterion as Markdown")
    p.add_argument("--compare", nargs=2, metavar=("OLD", "NEW"),
                   help="print the pass rates of two result TSVs side by side and exit")
    p.add_argument("--cases", default=os.path.join(here, "cad_corpus_cases.txt"),
                   help="the ctest cases (default %(default)s)")
    p.add_argument("--case", help="run one case of --cases (exit 0 pass, 1 fail, 77 skip)")
    p.add_argument("--fetch-cases", action="store_true",
                   help="fetch the models of --cases into --cache (exit 77 when impossible)")
    return p.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    args.cache = os.path.abspath(args.cache)  # the CLI runs in a temporary folder
    if args.compare:
        compare(*args.compare)
        return 0
    if args.fetch_cases:
        return fetch_cases(read_cases(args.cases), args.cache)
    if args.list:
        for model, kind in corpus(args.cache, args.sample, args.seed):
            print(f"{kind}\t{model}")
        return 0
    if not args.table:
        find_build_files(args)
    if args.case:
        return run_case(args.case, read_cases(args.cases), args)
    if args.table:
        rows = read_table(args.table)
    else:
        models = ([(os.path.abspath(m), "given") for m in args.models] if args.models
                  else corpus(args.cache, args.sample, args.seed))
        rows = run_corpus(models, args)
    if args.failures:
        write_failures(rows, args.failures)
    print_rates(rows, "pass rates (criterion judged on the models where it applies)")
    for name, text in CRITERIA:
        print(f"  {name}: {text}")
    for name, names in AGGREGATES:
        print(f"  {name}: {', '.join(names)}")
    print_slowest(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
