"""matplotlib's backend: only the command chooses it (Agg); the library never does, and
its figures (``matplotlib.figure.Figure``, no pyplot) save PNGs with no display.

Each check runs in a fresh interpreter, where nothing has chosen a backend or
imported pyplot yet."""
import json
import os
import subprocess
import sys
import textwrap

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROBOCUP = os.path.join(ROOT, "configs", "scenarios", "robocup_paper.toml")


def _python(code: str) -> dict:
    """Run ``code`` in a fresh interpreter without a display; return the JSON it prints last."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MPLBACKEND")}
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_importing_the_library_leaves_the_backend_alone():
    out = _python("""
        import importlib, json, pkgutil, sys
        import matplotlib
        matplotlib.use("svg")  # a notebook user's choice, made first
        import hga_jax, hga_jax.host, hga_jax.study
        names = sorted(m.name for pkg in (hga_jax.host, hga_jax.study)
                       for m in pkgutil.iter_modules(pkg.__path__, pkg.__name__ + "."))
        for name in names:
            importlib.import_module(name)
        print(json.dumps({"backend": matplotlib.get_backend(), "modules": names,
                          "pyplot": "matplotlib.pyplot" in sys.modules}))
    """)
    assert {"hga_jax.host.cli", "hga_jax.host.plots", "hga_jax.host.report",
            "hga_jax.study.figures", "hga_jax.study.analyses",
            "hga_jax.study.run"} <= set(out["modules"])
    assert out["backend"] == "svg"
    assert not out["pyplot"]  # pyplot is never imported when the library is


def test_the_command_chooses_agg():
    out = _python(f"""
        import json
        import matplotlib
        matplotlib.use("svg")
        from hga_jax.host.cli import main
        before = matplotlib.get_backend()
        code = main(["check", {ROBOCUP!r}])
        print(json.dumps({{"before": before, "after": matplotlib.get_backend(), "code": code}}))
    """)
    assert (out["before"], out["after"].lower(), out["code"]) == ("svg", "agg", 0)



def test_a_command_that_draws_nothing_does_not_import_matplotlib(tmp_path):
    """``check`` and ``exact`` without plots leave matplotlib unimported (it costs a
    start-up); drawing later still uses Agg, whatever MPLBACKEND the shell had."""
    out = _python(f"""
        import json, os, sys
        os.environ["MPLBACKEND"] = "TkAgg"  # interactive: would need a display
        from hga_jax.host.cli import main
        codes = [main(["check", {ROBOCUP!r}]),
                 main(["exact", {ROBOCUP!r}, "--out", {str(tmp_path / "a")!r}, "--no-cache"])]
        before = "matplotlib" in sys.modules
        codes.append(main(["exact", {ROBOCUP!r}, "--out", {str(tmp_path / "b")!r}, "--plot",
                           "--no-cache"]))
        import matplotlib
        print(json.dumps({{"before": before, "codes": codes, "backend": matplotlib.get_backend()}}))
    """)
    assert out["codes"] == [0, 0, 0] and out["before"] is False
    assert out["backend"].lower() == "agg"
    assert (tmp_path / "b" / "path.png").stat().st_size > 10_000

FIGURES = """
    import json, os, sys
    import matplotlib
    matplotlib.use("TkAgg")  # interactive: pyplot would need a display to draw with it
    import matplotlib.image as mpimg
    import numpy as np
    from hga_jax.host.config import load_scenario
    from hga_jax.host.plots import plot_convergence, plot_path, save_figure
    from hga_jax.model.path import evaluate_path
    from hga_jax.study import figures, summary, table

    def doc(config, family, scene, gaps, population=10, generations=4):
        n = len(gaps)
        hit = [g is not None and g < 1e-6 for g in gaps]
        gen = [2 if h else -1 for h in hit]
        evals = [population * 3 if h else None for h in hit]
        settings = {"population": population, "generations": generations}
        return {"config": config, "family": family, "scenario": scene, "obstacles": 3,
                "seed": 0, "runs": n, "settings": settings, "optimum": 2.0,
                "evaluations_per_run": population * (generations + 1), "search_s": 0.01 * n,
                "columns": {"run": list(range(n)), "length": [2.0 * (1 + (g or 1)) for g in gaps],
                            "feasible": [g is not None for g in gaps], "hit": hit,
                            "gap": gaps, "generation_1pct": gen, "evaluations_1pct": evals,
                            "generation_5pct": gen, "evaluations_5pct": evals,
                            "generation_hit": gen, "evaluations_hit": evals},
                "curves": {"best_so_far_gap_m": [[0.5, 0.2, 0.1, 0.0, 0.0]] * 3}}

    docs = [doc("a", "f", "s0", [0.0, 0.1, None, 0.0]), doc("b", "f", "s0", [0.2, 0.0, 0.0, 0.3]),
            doc("a", "g", "s1", [0.0, 0.0, 0.05, 0.0]), doc("b", "g", "s1", [None, 0.4, 0.0, 0.0])]
    tab = table.build("t", docs)
    rows = summary.summarize(tab, ["a", "b"])
    folder = sys.argv[1]
    files = figures.all_figures(tab, docs, rows, ["a", "b"], folder)
    sc = load_scenario(sys.argv[2])
    path = evaluate_path(sc, list(range(sc.n)), [1] + [0] * sc.n + [1])
    files.append(str(save_figure(plot_path(sc, path.segments), os.path.join(folder, "path.png"))))
    best = np.array([[1.0, 2.0], [2.0, 3.0], [3.0, 3.5]])
    files.append(str(save_figure(plot_convergence(best, best / 2, optimum_fitness=4.0),
                                 os.path.join(folder, "convergence_host.png"))))
    images = {}
    for f in files:
        im = mpimg.imread(f)
        images[os.path.basename(f)] = {"shape": list(im.shape), "std": float(im[..., :3].std())}
    print(json.dumps({"backend": matplotlib.get_backend(), "images": images,
                      "pyplot": "matplotlib.pyplot" in sys.modules}))
"""


@pytest.mark.slow  # no display: test_a_command_that_draws_nothing_does_not_import_matplotlib (a plot)
def test_figures_save_pngs_with_no_display(tmp_path):
    code = FIGURES.replace("sys.argv[1]", repr(str(tmp_path))).replace("sys.argv[2]", repr(ROBOCUP))
    out = _python(code)
    assert sorted(out["images"]) == ["anytime.png", "convergence.png", "convergence_host.png",
                                     "evaluations_ecdf.png", "gap_ecdf.png", "hit_rate.png",
                                     "path.png", "time_ecdf.png"]
    for name, im in out["images"].items():
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        h, w, channels = im["shape"]
        assert h > 150 and w > 300 and channels == 4, name
        assert im["std"] > 0.01, name  # something is drawn on the white
    assert out["backend"].lower() == "tkagg" and not out["pyplot"]


def test_the_study_figure_helper_needs_no_pyplot():
    out = _python("""
        import json, sys
        import matplotlib
        matplotlib.use("svg")
        from hga_jax.study.figures import subplots
        fig, axes = subplots(1, 2, figsize=(6, 3), sharey=True)
        print(json.dumps({"size": fig.get_size_inches().tolist(), "axes": len(axes),
                          "shared": axes[1].get_shared_y_axes().joined(axes[0], axes[1]),
                          "pyplot": "matplotlib.pyplot" in sys.modules}))
    """)
    assert out == {"size": [6.0, 3.0], "axes": 2, "shared": True, "pyplot": False}
