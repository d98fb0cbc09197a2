"""Make the pictures of docs/guide/actuators.md from the example files as they are.

    python docs/make_actuator_pictures.py            (from the project root)

Each picture is the project's own plot (:func:`linkage_fmu.plot.linkage`) of an example
driven by several actuators, at the state :data:`PICTURES` gives it; the page shows the
call under each picture. ``docs/excavator_dig.gif`` is the excavator over the digging
cycle of ``examples/excavator_cosim/run.py`` (:func:`linkage_fmu.plot.animate` over
its cylinders' motion).
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: example -> (its state and loads, the picture)
PICTURES = {
    "five_bar": (dict(theta_A=1.9, theta_E=1.2, omega_A=2.0, P=10.0), "five_bar_forces.png"),
    "dump_body": (dict(s_P=0.3, v_P=0.05, W=20000.0), "dump_body_forces.png"),
    "excavator": (dict(s_cyl1=0.2, s_cyl2=0.1, s_cyl3=0.1, F_T=15000.0),
                  "excavator_forces.png"),
}


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import linkage_fmu
    from linkage_fmu import plot

    for name, (state, picture) in PICTURES.items():
        fig = plot.linkage(linkage_fmu.load(ROOT / "examples" / f"{name}.toml"), **state)
        fig.savefig(ROOT / "docs" / picture, dpi=90)
        print(f"docs/{picture}")
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "excavator_cosim", ROOT / "examples" / "excavator_cosim" / "run.py")
    run = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run)
    rows = run.cycle(0.25)
    plot.animate(linkage_fmu.load(ROOT / "examples" / "excavator.toml"),
                 ROOT / "docs" / "excavator_dig.gif", what="efforts", t=rows.pop("time"),
                 motion=rows, fps=6, dpi=60)
    print("docs/excavator_dig.gif")


if __name__ == "__main__":
    main()
