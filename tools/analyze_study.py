#!/usr/bin/env python3
"""Analyse vergence study CSV files (paper Sec. 5, Fig. 7).

usage: analyze_study.py FILE.csv [FILE.csv ...] --out DIR [--pool-observers]

Hit study (`vergence study hit`):
- a linear mixed model of the miss distance (error_m) with condition,
  direction and path as fixed effects and participant as a random intercept
  (statsmodels MixedLM, REML; one participant: ordinary least squares, said so);
- its estimated marginal means per condition (averaged over direction and
  path, equal weights) with 95 % Wald confidence intervals;
- the three pairwise condition contrasts from the model, Holm-corrected, with
  a model-based effect size d = contrast / sqrt(participant variance +
  residual variance);
- the paper's one-way ANOVAs beside it (overall: the paper's F(2, 333) = 3.99;
  per direction: its F(2, 165) figures), and the raw means with 95 % CIs;
- hit_errors.png: mean error with 95 % CI by condition, overall and per
  direction (the paper's Fig. 7).

Preference study (`vergence study preference`): how often the optimized
version was chosen, a two-sided exact binomial test against chance (the
paper: 85.6 %, p < 0.01), overall, per scene and per saliency; across
participants, a one-sample t-test of each participant's fraction against 50 %
(two or more participants); preference.png.

Writes DIR/summary.md (for people) and DIR/summary.json (for scripts).
Several files (participants) are analysed together. Simulated (observer
"model", "model-cpu", "model-2cue", "model-2cue-cpu") and human trials are
never pooled unless --pool-observers says so; the report names the observers. Needs Debian's python3-numpy, python3-scipy,
python3-matplotlib, python3-statsmodels: run under /usr/bin/python3 (it
re-runs itself there when the current python lacks them).
"""
import csv
import json
import math
import os
import statistics
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
        import statsmodels  # noqa: F401
    except ImportError as e:
        debian = "/usr/bin/python3"
        if os.path.realpath(sys.executable) != os.path.realpath(debian) and os.path.exists(debian) \
                and not os.environ.get("VG_ANALYZE_REEXEC"):
            os.environ["VG_ANALYZE_REEXEC"] = "1"
            os.execv(debian, [debian] + sys.argv)
        die(f"{e.name} is missing: install python3-numpy python3-scipy python3-matplotlib python3-statsmodels "
            f"(Debian) and run under /usr/bin/python3", 3)


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------

def read_rows(paths, pool_observers=False):
    rows = {"hit": [], "preference": []}
    observers = {}
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
            observers.setdefault(r.get("observer") or "human", path)
    if len(observers) > 1 and not pool_observers:
        (a, pa), (b, pb) = sorted(observers.items())[:2]
        die(f"{pb}: its {b} trials would pool with the {a} trials of {pa}: analyse them apart, "
            f"or pass --pool-observers", 2)
    rows["observers"] = sorted(observers)
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


def holm(pvalues):
    """Holm's step-down adjustment (Holm 1979): the k-th smallest of m p-values
    times (m - k + 1), made monotone, capped at 1."""
    order = sorted(range(len(pvalues)), key=lambda i: pvalues[i])
    out, running = [0.0] * len(pvalues), 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(pvalues) - rank) * pvalues[i]))
        out[i] = running
    return out


PAIRS = [("original", "manipulated"), ("original", "optimized"), ("manipulated", "optimized")]
FORMULA = "error_m ~ C(condition, Treatment('original')) + C(direction) + C(path)"


def mixed_model(rows):
    """error_m ~ condition + direction + path, participant random intercept.
    Returns the fit's figures, the estimated marginal means and the pairwise
    contrasts (Holm), or None when the design cannot be fitted."""
    import numpy as np
    import pandas as pd
    import statsmodels.formula.api as smf
    from scipy import stats
    import warnings
    df = pd.DataFrame({"error_m": [float(r["error_m"]) for r in rows],
                       "condition": [r["condition"] for r in rows],
                       "direction": [r["direction"] for r in rows],
                       "path": [r["path"] for r in rows],
                       "participant": [r["participant"] for r in rows]})
    if df["condition"].nunique() < 3 or df["direction"].nunique() < 2 or df["path"].nunique() < 2:
        return None
    participants = df["participant"].nunique()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # convergence chatter; the figures say what was fitted
        if participants >= 2:
            fit = smf.mixedlm(FORMULA, df, groups=df["participant"]).fit(reml=True)
            kind = "linear mixed model (REML), participant random intercept"
            group_var = float(fit.cov_re.iloc[0, 0])
            resid_var = float(fit.scale)
            names = list(fit.fe_params.index)
            beta = fit.fe_params.values
            cov = fit.cov_params().loc[names, names].values
        else:
            fit = smf.ols(FORMULA, df).fit()
            kind = "ordinary least squares (one participant: no random effect)"
            group_var, resid_var = 0.0, float(fit.scale)
            names = list(fit.params.index)
            beta = fit.params.values
            cov = fit.cov_params().values
    # A design row averaged over direction and path (equal weights) for each condition.
    def row_for(condition):
        v = np.zeros(len(names))
        for i, n in enumerate(names):
            if n == "Intercept":
                v[i] = 1.0
            elif n.startswith("C(condition"):
                v[i] = 1.0 if n.endswith(f"[T.{condition}]") else 0.0
            elif n.startswith("C(direction)") or n.startswith("C(path)"):
                v[i] = 0.5  # two levels each: the non-reference one half the time
        return v
    z = stats.norm.ppf(0.975)
    emm = {}
    for c in CONDITIONS:
        L = row_for(c)
        m, se = float(L @ beta), float(np.sqrt(L @ cov @ L))
        emm[c] = {"emm": m, "se": se, "ci95": [m - z * se, m + z * se]}
    sd = math.sqrt(group_var + resid_var)
    contrasts, raw = {}, []
    for a, b in PAIRS:
        L = row_for(b) - row_for(a)
        est, se = float(L @ beta), float(np.sqrt(L @ cov @ L))
        zval = est / se
        p = float(2 * stats.norm.sf(abs(zval)))
        contrasts[f"{b} - {a}"] = {"estimate": est, "se": se, "z": zval, "p": p,
                                   "ci95": [est - z * se, est + z * se], "d": est / sd if sd > 0 else None}
        raw.append(p)
    for (k, v), ph in zip(contrasts.items(), holm(raw)):
        v["p_holm"] = ph
    coef = {n: {"estimate": float(beta[i]), "se": float(np.sqrt(cov[i, i]))} for i, n in enumerate(names)}
    return {"model": kind, "formula": FORMULA, "participants": participants, "n": len(df),
            "participant_variance": group_var, "residual_variance": resid_var, "fixed_effects": coef,
            "emm": emm, "contrasts": contrasts}


def analyze_hit(rows):
    errors = {c: {d: [] for d in DIRECTIONS + ["all"]} for c in CONDITIONS}
    for r in rows:
        c, d = r["condition"], r["direction"]
        if c not in errors or d not in DIRECTIONS:
            die(f"unknown condition or direction in trial {r['trial']} of {r['participant']}", 4)
        e = float(r["error_m"])
        errors[c][d].append(e)
        errors[c]["all"].append(e)
    out = {"trials": len(rows), "participants": sorted({r["participant"] for r in rows}), "conditions": {},
           "anova": {}, "mixed": mixed_model(rows)}
    for c in CONDITIONS:
        out["conditions"][c] = {d: mean_ci(errors[c][d]) for d in DIRECTIONS + ["all"]}
    for d in ["all"] + DIRECTIONS:
        out["anova"][d] = anova([errors[c][d] for c in CONDITIONS])
    # What each condition did to the ball as shown (ball_mid_jnd: files
    # written before the column have none).
    ball = {c: {d: [] for d in DIRECTIONS} for c in CONDITIONS}
    for r in rows:
        if r.get("ball_mid_jnd") not in (None, ""):
            ball[r["condition"]][r["direction"]].append(float(r["ball_mid_jnd"]))
    if any(v for c in ball.values() for v in c.values()):
        out["ball_mid_jnd"] = {c: {d: statistics.median(v) if v else None for d, v in ball[c].items()}
                               for c in CONDITIONS}
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
           "by_scene": {}, "by_saliency": {}, "across_participants": None}
    # Across participants: each one's fraction, one-sample t-test against 50 %.
    fractions = []
    for who in out["participants"]:
        mine = [int(r["chose_optimized"]) for r in rows if r["participant"] == who]
        fractions.append(sum(mine) / len(mine))
    if len(fractions) >= 2:
        t = stats.ttest_1samp(fractions, 0.5)
        out["across_participants"] = {"participants": len(fractions), "mean_fraction": sum(fractions) / len(fractions),
                                      "t": float(t.statistic), "df": len(fractions) - 1, "p": float(t.pvalue)}
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


def summary_md(files, hit, pref, observers):
    names = {"model": "simulated (observer model, the engine's frames)",
             "model-cpu": "simulated (observer model, CPU view)",
             "model-2cue": "simulated (two-cue observer: disparity and size, the engine's frames)",
             "model-2cue-cpu": "simulated (two-cue observer: disparity and size, CPU view)", "human": "human"}
    lines = ["# Study analysis", "", "Files: " + ", ".join(f"`{f}`" for f in files), "",
             "Observers: " + ", ".join(names.get(o, o) for o in observers) +
             (" (pooled on request)" if len(observers) > 1 else "") + ".", ""]
    if hit:
        lines += ["## Hit prediction (paper Sec. 5, Fig. 7)", "",
                  f"{hit['trials']} trials, participants: {', '.join(hit['participants'])}.", "",
                  "Mean error in metres with 95 % confidence interval:", "",
                  "| condition | all | near-to-far | far-to-near |", "|---|---|---|---|"]
        for c in CONDITIONS:
            s = hit["conditions"][c]
            lines.append(f"| {c} | {fmt_ci(s['all'])} | {fmt_ci(s['near-to-far'])} | {fmt_ci(s['far-to-near'])} |")
        mm = hit["mixed"]
        if mm:
            lines += ["", f"Model: {mm['model']}, `{mm['formula']}`, {mm['n']} trials of {mm['participants']} "
                      f"participant(s); participant variance {mm['participant_variance']:.4g}, residual variance "
                      f"{mm['residual_variance']:.4g} (m^2).", "",
                      "Estimated marginal means (equal weights over direction and path), 95 % Wald CI:", "",
                      "| condition | EMM (m) | SE | 95 % CI |", "|---|---:|---:|---|"]
            for c in CONDITIONS:
                e = mm["emm"][c]
                lines.append(f"| {c} | {e['emm']:.3f} | {e['se']:.3f} | [{e['ci95'][0]:.3f}, {e['ci95'][1]:.3f}] |")
            lines += ["", "Pairwise contrasts from the model, Holm-corrected; d = contrast / sqrt(participant + "
                      "residual variance):", "", "| contrast | estimate (m) | 95 % CI | z | p | p (Holm) | d |",
                      "|---|---:|---|---:|---:|---:|---:|"]
            for k, v in mm["contrasts"].items():
                d_ = "-" if v["d"] is None else f"{v['d']:.3f}"
                lines.append(f"| {k} | {v['estimate']:.3f} | [{v['ci95'][0]:.3f}, {v['ci95'][1]:.3f}] | "
                             f"{v['z']:.2f} | {v['p']:.4g} | {v['p_holm']:.4g} | {d_} |")
        else:
            lines += ["", "Model: not fitted (every condition, both directions and both paths are needed)."]
        lines += ["", "The paper's one-way ANOVAs over the three conditions, for comparison (paper: all throws "
                  "F(2, 333) = 3.99; per direction F(2, 165)):", "",
                  f"- all throws: {fmt_anova(hit['anova']['all'])}"]
        for d in DIRECTIONS:
            lines.append(f"- {d}: {fmt_anova(hit['anova'][d])}")
        if "ball_mid_jnd" in hit:
            cell = lambda v: "-" if v is None else f"{v:.2f}"
            lines += ["", "What each condition did to the ball as shown: the paper's MID distortion of its "
                      "displayed vergence against g over the visible flight (`ball_mid_jnd`, JND), median:", "",
                      "| condition | near-to-far | far-to-near |", "|---|---:|---:|"]
            for c in CONDITIONS:
                b = hit["ball_mid_jnd"][c]
                lines.append(f"| {c} | {cell(b['near-to-far'])} | {cell(b['far-to-near'])} |")
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
        ap = pref["across_participants"]
        lines += ["", "Across participants: " + (
            f"mean fraction {100 * ap['mean_fraction']:.1f} % over {ap['participants']}, one-sample t-test "
            f"against 50 %: t({ap['df']}) = {ap['t']:.3f}, p = {ap['p']:.4g}." if ap else
            "one participant: no test across participants.")]
        lines += ["", "![preference](preference.png)", ""]
    return "\n".join(lines)


def main(argv):
    files, out, pool = [], None, False
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
        if a == "--pool-observers":
            pool = True
            i += 1
            continue
        if a.startswith("-"):
            die(f"unknown option {a} (see --help)")
        files.append(a)
        i += 1
    if not files or not out:
        die("usage: analyze_study.py FILE.csv [FILE.csv ...] --out DIR")
    ensure_scientific_python()
    rows = read_rows(files, pool)
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        die(f"{out}: {e.strerror}", 3)
    result = {"files": files, "observers": rows["observers"]}
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
    md = summary_md(files, hit, pref, rows["observers"])
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(md + "\n")
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
