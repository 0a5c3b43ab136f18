"""One-axes report figures finished and written the same way for tools/report/papers.py's items."""
import os


def save_axes_figure(fig, ax, out_dir, rel, xlabel, ylabel, title):
    """Labels, grid and legend on ax, then fig written to out_dir/rel (PNG, 100 dpi) and closed; returns rel."""
    import matplotlib.pyplot as plt
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, rel), dpi=100)
    plt.close(fig)
    return rel
