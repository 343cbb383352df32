#!/usr/bin/env python3
"""Analyse vergence study CSV files (paper Sec. 5, Fig. 7).

usage: analyze_study.py FILE.csv [FILE.csv ...] --out DIR

Hit study (`vergence study hit`): mean error per condition with 95 % confidence
intervals (Student t), a one-way ANOVA over the three conditions overall and
per direction (F, degrees of freedom, p), Welch t-tests between conditions,
and a plot like the paper's Fig. 7 (hit_errors.png).

Preference study (`vergence study preference`): how often the optimized
version was chosen, a two-sided exact binomial test against chance (the
paper: 85.6 %, p < 0.01), per scene and saliency, and preference.png.

Writes DIR/summary.md (for people) and DIR/summary.json (for scripts).
Several files (participants) are pooled; every file must be a vergence study
CSV. Needs Debian's python3-numpy, python3-scipy, python3-matplotlib: run
under /usr/bin/python3 (it re-runs itself there when the current python
lacks them).
"""
import csv
import json
import math
import os
import sys

CONDITIONS = ["original", "manipulated", "optimized"]
DIRECTIONS = ["near-to-far", "far-to-near"]
HIT_NEEDS = ["participant", "study", "trial", "condition", "direction", "path", "error_m"]
PREF_NEEDS = ["participant", "study", "trial", "scene", "saliency", "chose_optimized"]


def die(msg, code=2):
    print(f"analyze_study: error: {msg}", file=sys.stderr)
    sys.exit(code)


def ensure_scientific_python():
    try:
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError as e:
        debian = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(debian) and os.path.exists(debian) \
                and not os.environ.get("VG_ANALYZE_REEXEC"):
            os.environ["VG_ANALYZE_REEXEC"] = "1"
            os.execv(debian, [debian] + sys.argv)
        die(f"{e.name} is missing: install python3-numpy python3-scipy python3-matplotlib "
            f"(Debian) and run under /usr/bin/python3", 3)


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------

def read_rows(paths):
    rows = {"hit": [], "preference": []}
    for path in paths:
        try:
            with open(path, newline="") as f:
                reader = csv.DictReader(f)
                header = reader.fieldnames or []
                data = list(reader)
        except OSError as e:
            die(f"{path}: {e.strerror}", 3)
        except csv.Error as e:
            die(f"{path}: not a CSV file ({e})", 4)
        if "study" not in header or not data:
            die(f"{path}: not a vergence study CSV with trials (header: {','.join(header[:4])}...)", 4)
        for n, r in enumerate(data, start=2):
            kind = r.get("study")
            needs = HIT_NEEDS if kind == "hit" else PREF_NEEDS if kind == "preference" else None
            if needs is None or any(r.get(k) in (None, "") for k in needs):
                die(f"{path}:{n}: not a complete hit or preference trial", 4)
            rows[kind].append(r)
    return rows


# ---------------------------------------------------------------------------
# Statistics
# ---------------------------------------------------------------------------

def mean_ci(values):
    from scipy import stats
    import numpy as np
    v = np.asarray(values, dtype=float)
    n = len(v)
    if n == 0:
        return {"n": 0, "mean": None, "ci95": None, "sd": None}
    m = float(v.mean())
    if n < 2:
        return {"n": n, "mean": m, "ci95": None, "sd": None}
    sd = float(v.std(ddof=1))
    half = float(stats.t.ppf(0.975, n - 1) * sd / math.sqrt(n))
    return {"n": n, "mean": m, "sd": sd, "ci95": [m - half, m + half]}


def anova(groups):
    """One-way ANOVA over the non-empty groups: F, (df_between, df_within), p."""
    from scipy import stats
    g = [x for x in groups if len(x) > 0]
    if len(g) < 2 or sum(len(x) for x in g) - len(g) < 1:
        return None
    res = stats.f_oneway(*g)
    n = sum(len(x) for x in g)
    return {"F": float(res.statistic), "df": [len(g) - 1, n - len(g)], "p": float(res.pvalue)}


def analyze_hit(rows):
    from scipy import stats
    errors = {c: {d: [] for d in DIRECTIONS + ["all"]} for c in CONDITIONS}
    for r in rows:
        c, d = r["condition"], r["direction"]
        if c not in errors or d not in DIRECTIONS:
            die(f"unknown condition or direction in trial {r['trial']} of {r['participant']}", 4)
        e = float(r["error_m"])
        errors[c][d].append(e)
        errors[c]["all"].append(e)
    out = {"trials": len(rows), "participants": sorted({r["participant"] for r in rows}), "conditions": {},
           "anova": {}, "welch": {}}
    for c in CONDITIONS:
        out["conditions"][c] = {d: mean_ci(errors[c][d]) for d in DIRECTIONS + ["all"]}
    for d in ["all"] + DIRECTIONS:
        out["anova"][d] = anova([errors[c][d] for c in CONDITIONS])
    for a, b in [("original", "manipulated"), ("original", "optimized"), ("manipulated", "optimized")]:
        x, y = errors[a]["all"], errors[b]["all"]
        if len(x) > 1 and len(y) > 1:
            t = stats.ttest_ind(x, y, equal_var=False)
            out["welch"][f"{a}-{b}"] = {"t": float(t.statistic), "p": float(t.pvalue)}
    return out, errors


def analyze_preference(rows):
    from scipy import stats

    def test(sub):
        n = len(sub)
        k = sum(int(r["chose_optimized"]) for r in sub)
        if n == 0:
            return None
        b = stats.binomtest(k, n, 0.5, alternative="two-sided")
        ci = b.proportion_ci(confidence_level=0.95, method="exact")
        return {"n": n, "chose_optimized": k, "fraction": k / n, "p": float(b.pvalue),
                "ci95": [float(ci.low), float(ci.high)]}

    out = {"trials": len(rows), "participants": sorted({r["participant"] for r in rows}), "all": test(rows),
           "by_scene": {}, "by_saliency": {}}
    for s in sorted({r["scene"] for r in rows}):
        out["by_scene"][s] = test([r for r in rows if r["scene"] == s])
    for s in sorted({r["saliency"] for r in rows}):
        out["by_saliency"][s] = test([r for r in rows if r["saliency"] == s])
    return out


# ---------------------------------------------------------------------------
# Plots and summary
# ---------------------------------------------------------------------------

COLORS = {"original": "#4c78a8", "manipulated": "#e45756", "optimized": "#54a24b"}


def plot_hit(result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    groups = ["all"] + DIRECTIONS
    fig, ax = plt.subplots(figsize=(6.4, 3.8), dpi=110)
    width = 0.26
    for i, c in enumerate(CONDITIONS):
        xs, ms, lo, hi = [], [], [], []
        for j, d in enumerate(groups):
            s = result["conditions"][c][d]
            if s["mean"] is None:
                continue
            xs.append(j + (i - 1) * width)
            ms.append(s["mean"])
            ci = s["ci95"] or [s["mean"], s["mean"]]
            lo.append(s["mean"] - ci[0])
            hi.append(ci[1] - s["mean"])
        ax.bar(xs, ms, width * 0.9, color=COLORS[c], label=c, yerr=[lo, hi], capsize=3,
               error_kw={"elinewidth": 1, "ecolor": "#333333"})
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(["all throws"] + DIRECTIONS)
    ax.set_ylabel("hit error (m)")
    a = result["anova"]["all"]
    sub = f"\none-way ANOVA F({a['df'][0]}, {a['df'][1]}) = {a['F']:.2f}, p = {a['p']:.3g}" if a else ""
    ax.set_title("Hit-prediction error, mean with 95 % CI (cf. paper Fig. 7)" + sub, fontsize=10)
    ax.legend(frameon=False, fontsize=9)
    ax.spines[["top", "right"]].set_visible(False)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_preference(result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    items = [("all", result["all"])] + list(result["by_scene"].items()) + \
        [(f"saliency: {k}", v) for k, v in result["by_saliency"].items()]
    items = [(k, v) for k, v in items if v]
    fig, ax = plt.subplots(figsize=(6.4, 3.4), dpi=110)
    xs = range(len(items))
    fr = [100 * v["fraction"] for _, v in items]
    lo = [100 * (v["fraction"] - v["ci95"][0]) for _, v in items]
    hi = [100 * (v["ci95"][1] - v["fraction"]) for _, v in items]
    ax.bar(xs, fr, 0.6, color=COLORS["optimized"], yerr=[lo, hi], capsize=3)
    ax.axhline(50, color="#888888", lw=1, ls="--")
    ax.set_xticks(list(xs))
    ax.set_xticklabels([k for k, _ in items], fontsize=8)
    ax.set_ylim(0, 100)
    ax.set_ylabel("optimized chosen (%)")
    ax.set_title("Preference for the optimized version, 95 % CI (exact)", fontsize=10)
    ax.spines[["top", "right"]].set_visible(False)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def fmt_ci(s):
    if s["mean"] is None:
        return "-"
    if not s["ci95"]:
        return f"{s['mean']:.3f} (n = {s['n']})"
    return f"{s['mean']:.3f} [{s['ci95'][0]:.3f}, {s['ci95'][1]:.3f}] (n = {s['n']})"


def fmt_anova(a):
    return "-" if not a else f"F({a['df'][0]}, {a['df'][1]}) = {a['F']:.3f}, p = {a['p']:.4g}"


def summary_md(files, hit, pref):
    lines = ["# Study analysis", "", "Files: " + ", ".join(f"`{f}`" for f in files), ""]
    if hit:
        lines += ["## Hit prediction (paper Sec. 5, Fig. 7)", "",
                  f"{hit['trials']} trials, participants: {', '.join(hit['participants'])}.", "",
                  "Mean error in metres with 95 % confidence interval:", "",
                  "| condition | all | near-to-far | far-to-near |", "|---|---|---|---|"]
        for c in CONDITIONS:
            s = hit["conditions"][c]
            lines.append(f"| {c} | {fmt_ci(s['all'])} | {fmt_ci(s['near-to-far'])} | {fmt_ci(s['far-to-near'])} |")
        lines += ["", "One-way ANOVA over the three conditions:", "",
                  f"- all throws: {fmt_anova(hit['anova']['all'])}"]
        for d in DIRECTIONS:
            lines.append(f"- {d}: {fmt_anova(hit['anova'][d])}")
        if hit["welch"]:
            lines += ["", "Welch t-tests: " + "; ".join(
                f"{k}: t = {v['t']:.2f}, p = {v['p']:.3g}" for k, v in hit["welch"].items())]
        lines += ["", "![hit errors](hit_errors.png)", ""]
    if pref:
        a = pref["all"]
        lines += ["## Preference (paper Sec. 5)", "",
                  f"{pref['trials']} trials, participants: {', '.join(pref['participants'])}.", "",
                  f"The optimized version was chosen in {a['chose_optimized']} of {a['n']} trials "
                  f"({100 * a['fraction']:.1f} %, 95 % CI {100 * a['ci95'][0]:.1f}-{100 * a['ci95'][1]:.1f} %); "
                  f"two-sided binomial test against 50 %: p = {a['p']:.4g}.", "",
                  "| subset | chosen / trials | % | p |", "|---|---|---|---|"]
        for name, group in [("scene", pref["by_scene"]), ("saliency", pref["by_saliency"])]:
            for k, v in group.items():
                lines.append(f"| {name} {k} | {v['chose_optimized']} / {v['n']} | {100 * v['fraction']:.1f} | "
                             f"{v['p']:.4g} |")
        lines += ["", "![preference](preference.png)", ""]
    return "\n".join(lines)


def main(argv):
    files, out = [], None
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__)
            return 0
        if a == "--out":
            if i + 1 >= len(argv):
                die("--out needs a folder")
            out = argv[i + 1]
            i += 2
            continue
        if a.startswith("-"):
            die(f"unknown option {a} (see --help)")
        files.append(a)
        i += 1
    if not files or not out:
        die("usage: analyze_study.py FILE.csv [FILE.csv ...] --out DIR")
    ensure_scientific_python()
    rows = read_rows(files)
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        die(f"{out}: {e.strerror}", 3)
    result = {"files": files}
    hit = pref = None
    if rows["hit"]:
        hit, _ = analyze_hit(rows["hit"])
        plot_hit(hit, os.path.join(out, "hit_errors.png"))
        result["hit"] = hit
    if rows["preference"]:
        pref = analyze_preference(rows["preference"])
        plot_preference(pref, os.path.join(out, "preference.png"))
        result["preference"] = pref
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(result, f, indent=1)
    md = summary_md(files, hit, pref)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(md + "\n")
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
