"""Plot κ(s) of the original, the reference smoother and Fairway from the CSV files that
`cargo run --release -p fairway --example quality_table -- --dump DIR` writes.

    python3 scripts/plot_kappa.py DIR OUT.png CASE [CASE ...]

(needs matplotlib: install it into a throw-away venv; not part of CI)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    src, out, cases = sys.argv[1], sys.argv[2], sys.argv[3:]
    fig, axes = plt.subplots(len(cases), 1, figsize=(11, 2.6 * len(cases)), squeeze=False)
    for ax, case in zip(axes[:, 0], cases):
        with open(f"{src}/{case}.csv") as f:
            rows = list(csv.reader(f))
        head, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
        s = [r[0] for r in data]
        for j, (name, style) in enumerate(zip(head[1:], ["-", "-", "-"]), start=1):
            ax.plot(s, [r[j] for r in data], style, lw=0.8 if j == 1 else 1.3, label=name,
                    color=["0.65", "tab:orange", "tab:blue"][j - 1])
        ax.set_title(case, fontsize=9)
        ax.set_xlabel("s / L", fontsize=8)
        ax.set_ylabel("κ", fontsize=8)
        ax.legend(fontsize=7, loc="upper right")
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
