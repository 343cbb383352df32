#!/usr/bin/env python3
"""Studies, their CSV logs and the analysis tool, as a user runs them (issue 6).

usage: study_test.py VERGENCE CASE     (run by CTest under /usr/bin/python3)

  study       a simulated-observer hit study (>= 300 trials per condition,
              fixed seed) through tools/analyze_study.py; the observer errs
              more under manipulated than under original disparity
  analysis    the tool's F, degrees of freedom, p and binomial test against an
              independent computation and scipy on fixed CSVs
  durability  kill -9 during a study leaves every finished trial, parseable;
              --resume continues at the next trial and ends where an
              uninterrupted run ends
  bad_input   missing or bad participant, another participant's file, an
              existing file, corrupt files, no display: one error, nothing
              overwritten
"""
import csv
import hashlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TOOL = os.path.join(ROOT, "tools", "analyze_study.py")


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def run(args, ok=True, env=None, timeout=600):
    p = subprocess.run([VERGENCE] + args, capture_output=True, text=True, timeout=timeout, env=env)
    if ok and p.returncode != 0:
        fail(f"vergence {' '.join(args)} exited {p.returncode}\n{p.stderr}")
    return p


def rows(path):
    with open(path, newline="") as f:
        r = list(csv.reader(f))
    if not r or any(len(x) != len(r[0]) for x in r):
        fail(f"{path}: torn or ragged CSV")
    return r


def one_error(p, must, what):
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    errors = [l for l in lines if "error:" in l]
    print(f"{what}: exit {p.returncode}: {p.stderr.strip()}")
    if not 0 < p.returncode < 128:
        fail(f"{what}: exit code {p.returncode} (want 1..127)")
    if len(errors) != 1:
        fail(f"{what}: want one error line, got {len(errors)}: {lines}")
    if must not in errors[0]:
        fail(f"{what}: the error does not say '{must}'")


def sha(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def model(args, out, **kw):
    return run(["study", "hit", "--observer", "model", "--observer-view", "cpu"] + args + ["--out", out], **kw)


# ---------------------------------------------------------------------------

def case_study():
    tmp = tempfile.mkdtemp(prefix="vergence_study_")
    out = os.path.join(tmp, "sim.csv")
    t0 = time.time()
    model(["--participant", "sim", "--trials", "960", "--seed", "2024"], out)
    r = rows(out)
    header, data = r[0], r[1:]
    col = {n: i for i, n in enumerate(header)}
    counts = {c: sum(1 for x in data if x[col["condition"]] == c) for c in ("original", "manipulated", "optimized")}
    print(f"960 simulated trials in {time.time() - t0:.1f} s: {counts}")
    if len(data) != 960 or min(counts.values()) < 300:
        fail(f"want 960 trials, >= 300 per condition: {len(data)}, {counts}")
    an = os.path.join(tmp, "analysis")
    p = subprocess.run([sys.executable, TOOL, out, "--out", an], capture_output=True, text=True, timeout=300)
    if p.returncode:
        fail(f"analyze_study.py exited {p.returncode}\n{p.stderr}")
    print(p.stdout)
    s = json.load(open(os.path.join(an, "summary.json")))["hit"]
    for f in ("hit_errors.png", "summary.md"):
        data_ = open(os.path.join(an, f), "rb").read()
        if not data_ or (f.endswith(".png") and data_[:8] != b"\x89PNG\r\n\x1a\n"):
            fail(f"{f} missing or not a PNG")
    orig, mani = s["conditions"]["original"]["all"], s["conditions"]["manipulated"]["all"]
    # Physics: compressed disparity moves the ball wrongly in depth, so a
    # disparity-only observer misses by more (and the CIs do not overlap).
    if not (mani["mean"] > orig["mean"] and mani["ci95"][0] > orig["ci95"][1]):
        fail(f"manipulated {mani} is not worse than original {orig}")
    if not s["anova"]["all"]["p"] < 0.01 or s["anova"]["all"]["df"] != [2, 957]:
        fail(f"ANOVA {s['anova']['all']}")
    # The ball as shown, per row (ball_mid_jnd) and in the summary: g is
    # itself (0 on every original row); h distorts the near-to-far ball's
    # motion in depth and f restores much of it (issue 39).
    ball = s.get("ball_mid_jnd")
    print(f"ball_mid_jnd medians: {ball}")
    originals = [float(x[col["ball_mid_jnd"]]) for x in data if x[col["condition"]] == "original"]
    if max(originals) != 0:
        fail(f"an original row's ball_mid_jnd is {max(originals)}, not 0")
    h, f = ball["manipulated"]["near-to-far"], ball["optimized"]["near-to-far"]
    if not (h >= 1.5 and f < 0.8 * h):
        fail(f"near-to-far ball_mid_jnd medians: manipulated {h}, optimized {f} (want h >= 1.5, f < 0.8 h)")


def case_analysis():
    import numpy as np
    from scipy import stats
    tmp = tempfile.mkdtemp(prefix="vergence_analysis_")
    hit = os.path.join(HERE, "data", "hit_fixed.csv")
    pref = os.path.join(HERE, "data", "preference_fixed.csv")
    # Through `python3` on PATH too: the tool re-runs itself under Debian's python.
    for py in (sys.executable, "python3"):
        p = subprocess.run([py, TOOL, hit, pref, "--out", tmp], capture_output=True, text=True, timeout=300)
        if p.returncode:
            fail(f"{py} analyze_study.py exited {p.returncode}\n{p.stderr}")
    s = json.load(open(os.path.join(tmp, "summary.json")))
    data = list(csv.DictReader(open(hit)))
    for d in ("all", "near-to-far", "far-to-near"):
        groups = [np.array([float(r["error_m"]) for r in data if r["condition"] == c and d in ("all", r["direction"])])
                  for c in ("original", "manipulated", "optimized")]
        # F by hand: between- and within-group sums of squares.
        allv = np.concatenate(groups)
        ssb = sum(len(g) * (g.mean() - allv.mean()) ** 2 for g in groups)
        ssw = sum(((g - g.mean()) ** 2).sum() for g in groups)
        dfb, dfw = len(groups) - 1, len(allv) - len(groups)
        F = (ssb / dfb) / (ssw / dfw)
        p_ = stats.f.sf(F, dfb, dfw)
        ref = stats.f_oneway(*groups)
        a = s["hit"]["anova"][d]
        print(f"{d}: tool F({a['df'][0]}, {a['df'][1]}) = {a['F']:.6f}, p = {a['p']:.6g}; "
              f"by hand F = {F:.6f}, p = {p_:.6g}; scipy F = {ref.statistic:.6f}, p = {ref.pvalue:.6g}")
        if a["df"] != [dfb, dfw] or abs(a["F"] - F) > 1e-9 * F or abs(a["p"] - p_) > 1e-9 * max(p_, 1e-300) \
                or abs(a["F"] - ref.statistic) > 1e-9 * F or abs(a["p"] - ref.pvalue) > 1e-12:
            fail(f"{d}: the tool's ANOVA differs")
        for c, g in zip(("original", "manipulated", "optimized"), groups):
            m = s["hit"]["conditions"][c][d]
            half = stats.t.ppf(0.975, len(g) - 1) * g.std(ddof=1) / np.sqrt(len(g))
            if abs(m["mean"] - g.mean()) > 1e-12 or abs(m["ci95"][1] - g.mean() - half) > 1e-9:
                fail(f"{c} {d}: mean/CI {m} vs {g.mean()} +- {half}")
    prefs = list(csv.DictReader(open(pref)))
    k, n = sum(int(r["chose_optimized"]) for r in prefs), len(prefs)
    b = stats.binomtest(k, n, 0.5)
    t = s["preference"]["all"]
    print(f"preference: tool {t['chose_optimized']}/{t['n']}, p = {t['p']:.6g}; scipy {k}/{n}, p = {b.pvalue:.6g}")
    if t["n"] != n or t["chose_optimized"] != k or abs(t["p"] - b.pvalue) > 1e-12:
        fail("the tool's binomial test differs")
    check_mixed_model(tmp)
    check_pooling_and_participants(tmp, pref)
    for bad, code in ((os.path.join(tmp, "missing.csv"), 3), (os.path.join(HERE, "study_test.py"), 4)):
        p = subprocess.run([sys.executable, TOOL, bad, "--out", tmp], capture_output=True, text=True)
        if p.returncode != code or len([l for l in p.stderr.splitlines() if "error:" in l]) != 1:
            fail(f"analyze_study.py {bad}: exit {p.returncode} (want {code}), {p.stderr}")


def check_mixed_model(tmp):
    """The tool's mixed model, marginal means and Holm-corrected contrasts
    against statsmodels' array API, a design matrix built here and
    statsmodels' own Holm (4 simulated participants, 192 trials)."""
    import numpy as np
    import statsmodels.api as sm
    from statsmodels.stats.multitest import multipletests
    path = os.path.join(HERE, "data", "hit_participants.csv")
    out = os.path.join(tmp, "mixed")
    p = subprocess.run([sys.executable, TOOL, path, "--out", out], capture_output=True, text=True, timeout=300)
    if p.returncode:
        fail(f"analyze_study.py exited {p.returncode}\n{p.stderr}")
    mm = json.load(open(os.path.join(out, "summary.json")))["hit"]["mixed"]
    data = list(csv.DictReader(open(path)))
    y = np.array([float(r["error_m"]) for r in data])
    # Columns: intercept, manipulated, optimized, near-to-far, straight (references: original,
    # far-to-near, ballistic: the alphabetically first, as patsy picks them).
    X = np.array([[1.0, r["condition"] == "manipulated", r["condition"] == "optimized",
                   r["direction"] == "near-to-far", r["path"] == "straight"] for r in data], dtype=float)
    groups = np.array([r["participant"] for r in data])
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = sm.MixedLM(y, X, groups).fit(reml=True)
    beta, cov = np.asarray(fit.fe_params), np.asarray(fit.cov_params())[:5, :5]
    tool = [v["estimate"] for v in mm["fixed_effects"].values()]
    print(f"mixed model: tool {np.round(tool, 6)}; statsmodels arrays {np.round(beta, 6)}")
    if mm["participants"] != 4 or not np.allclose(tool, beta, rtol=1e-5, atol=1e-7):
        fail("the tool's mixed-model coefficients differ")
    rows = {c: np.array([1, c == "manipulated", c == "optimized", 0.5, 0.5], dtype=float)
            for c in ("original", "manipulated", "optimized")}
    for c, L in rows.items():
        e = mm["emm"][c]
        if abs(e["emm"] - L @ beta) > 1e-6 or abs(e["se"] - np.sqrt(L @ cov @ L)) > 1e-6:
            fail(f"EMM {c}: tool {e}, here {L @ beta} +- {np.sqrt(L @ cov @ L)}")
    raw, tool_holm = [], []
    for a, b in (("original", "manipulated"), ("original", "optimized"), ("manipulated", "optimized")):
        v = mm["contrasts"][f"{b} - {a}"]
        L = rows[b] - rows[a]
        est, se = L @ beta, np.sqrt(L @ cov @ L)
        if abs(v["estimate"] - est) > 1e-6 or abs(v["se"] - se) > 1e-6:
            fail(f"contrast {b} - {a}: tool {v}, here {est} +- {se}")
        sd = np.sqrt(float(np.asarray(fit.cov_re)[0, 0]) + fit.scale)
        if abs(v["d"] - est / sd) > 1e-6:
            fail(f"effect size {b} - {a}: tool {v['d']}, here {est / sd}")
        raw.append(v["p"])
        tool_holm.append(v["p_holm"])
    ref = multipletests(raw, method="holm")[1]
    print(f"Holm: tool {np.round(tool_holm, 8)}, statsmodels {np.round(ref, 8)}")
    if not np.allclose(tool_holm, ref, rtol=1e-12, atol=1e-15):
        fail("the tool's Holm correction differs from statsmodels'")


def check_pooling_and_participants(tmp, pref):
    """A human and a simulated CSV are refused together, accepted with
    --pool-observers (and the report says so); the preference test across
    participants is scipy's one-sample t-test of their fractions."""
    from scipy import stats
    human = os.path.join(tmp, "human.csv")
    with open(os.path.join(HERE, "data", "hit_fixed.csv")) as f, open(human, "w") as g:
        g.write(f.read().replace(",model,", ",human,"))
    sim = os.path.join(HERE, "data", "hit_participants.csv")
    out = os.path.join(tmp, "pool")
    p = subprocess.run([sys.executable, TOOL, sim, human, "--out", out], capture_output=True, text=True)
    errors = [l for l in p.stderr.splitlines() if "error:" in l]
    print(f"simulated + human -> exit {p.returncode}: {p.stderr.strip()}")
    if p.returncode != 2 or len(errors) != 1 or "--pool-observers" not in errors[0]:
        fail("mixing simulated and human trials was not refused with one line")
    p = subprocess.run([sys.executable, TOOL, sim, human, "--out", out, "--pool-observers"], capture_output=True,
                       text=True, timeout=300)
    if p.returncode or "pooled on request" not in p.stdout:
        fail(f"--pool-observers: exit {p.returncode}, the report does not say the observers were pooled")
    two = os.path.join(tmp, "pref_two.csv")
    data = list(csv.DictReader(open(pref)))
    for i, r in enumerate(data):
        r["participant"] = "a" if i % 2 else "b"
    with open(two, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(data[0].keys()))
        w.writeheader()
        w.writerows(data)
    p = subprocess.run([sys.executable, TOOL, two, "--out", out], capture_output=True, text=True, timeout=300)
    ap = json.load(open(os.path.join(out, "summary.json")))["preference"]["across_participants"]
    fr = [sum(int(r["chose_optimized"]) for r in data if r["participant"] == w) /
          sum(1 for r in data if r["participant"] == w) for w in ("a", "b")]
    t = stats.ttest_1samp(fr, 0.5)
    print(f"across participants: tool t = {ap['t']:.6f}, p = {ap['p']:.6g}; scipy t = {t.statistic:.6f}, "
          f"p = {t.pvalue:.6g}")
    if ap["participants"] != 2 or abs(ap["t"] - t.statistic) > 1e-9 or abs(ap["p"] - t.pvalue) > 1e-9:
        fail("the tool's test across participants differs from scipy's")


def case_durability():
    tmp = tempfile.mkdtemp(prefix="vergence_k9_")
    out, ref = os.path.join(tmp, "k9.csv"), os.path.join(tmp, "ref.csv")
    args = ["study", "hit", "--observer", "model", "--observer-view", "cpu", "--participant", "k9", "--seed", "3"]
    p = subprocess.Popen([VERGENCE] + args + ["--trials", "100000", "--out", out], stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while time.time() < deadline:
        time.sleep(0.05)
        if os.path.exists(out) and open(out, "rb").read().count(b"\n") > 40:
            break
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    r = rows(out)
    done = len(r) - 1
    trials = [int(x[2]) for x in r[1:]]
    print(f"kill -9 left {done} finished trials")
    if done < 40 or trials != list(range(done)):
        fail(f"after kill -9: {done} trials numbered {trials[:5]}...")
    total = done + 24
    run(args + ["--trials", str(total), "--resume", "--out", out])
    run(args + ["--trials", str(total), "--out", ref])
    a, b = rows(out), rows(ref)
    k = a[0].index("utc")
    strip = lambda t: [x[:k] + x[k + 1:] for x in t]  # every column but the time of day
    if len(a) != total + 1 or strip(a) != strip(b):
        fail(f"resumed file ({len(a) - 1} trials) differs from an uninterrupted run ({len(b) - 1})")
    before = sha(out)
    q = run(args + ["--trials", str(total), "--resume", "--out", out])
    if sha(out) != before:
        fail("resuming a finished study changed the file")
    print(f"resumed at trial {done}, ended at {total} as an uninterrupted run does; {q.stderr.strip()}")


def case_bad_input():
    tmp = tempfile.mkdtemp(prefix="vergence_bad_")
    out = os.path.join(tmp, "a.csv")
    hit = ["study", "hit", "--observer", "model", "--observer-view", "cpu"]
    one_error(run(hit + ["--out", out], ok=False), "--participant", "no participant")
    one_error(run(hit + ["--participant", "a,b", "--out", out], ok=False), "participant", "bad participant id")
    one_error(run(hit + ["--participant", "a"], ok=False), "--out", "no --out")
    one_error(run(["study", "bogus"], ok=False), "bogus", "unknown study")
    if os.path.exists(out):
        fail("a CSV was written despite the errors")
    run(hit + ["--participant", "alice", "--trials", "6", "--out", out])
    h = sha(out)
    for args, must, what in (
            (["--participant", "bob"], "belongs to participant 'alice'", "another participant's file"),
            (["--participant", "bob", "--resume"], "belongs to participant 'alice'", "another participant, resume"),
            (["--participant", "alice"], "already exists", "existing file without --resume"),
            (["--participant", "alice", "--resume", "--seed", "99"], "--seed", "another seed on resume")):
        one_error(run(hit + args + ["--trials", "12", "--out", out], ok=False), must, what)
        if sha(out) != h:
            fail(f"{what}: the file changed")
    good = open(out).read()
    lines = good.splitlines(keepends=True)
    corrupt = {
        "torn": good + "alice,hit,6,3",
        "fields": good + "alice,hit,6\n",
        "header": "participant,trial\n" + "".join(lines[1:]),
        "binary": "\x00\x01garbage\n",
        "empty": "",
        "schedule": lines[0] + lines[2] + lines[1],
    }
    for name, text in corrupt.items():
        path = os.path.join(tmp, f"{name}.csv")
        open(path, "w").write(text)
        h = sha(path)
        one_error(run(hit + ["--participant", "alice", "--resume", "--trials", "12", "--out", path], ok=False),
                  path, f"corrupt CSV ({name})")
        if sha(path) != h:
            fail(f"corrupt CSV ({name}) was changed")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.setdefault("XDG_RUNTIME_DIR", "/tmp")
    one_error(run(["play"], ok=False, env=env), "display", "play without a display")
    study_out = os.path.join(tmp, "human.csv")
    one_error(run(["study", "hit", "--participant", "h", "--out", study_out], ok=False, env=env), "display",
              "a human study without a display")
    if os.path.exists(study_out):
        fail("a study that could not open its window left a CSV behind")
    replay = os.path.join(tmp, "bad.replay")
    open(replay, "w").write("10 key H\n5 key Q\n")
    one_error(run(["play", "--replay", replay], ok=False, env=env), "bad.replay:2", "replay out of order")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    VERGENCE = os.path.abspath(sys.argv[1])
    os.chdir(ROOT)
    {"study": case_study, "analysis": case_analysis, "durability": case_durability,
     "bad_input": case_bad_input}[sys.argv[2]]()
    print("ok")
