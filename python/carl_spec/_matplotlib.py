"""matplotlib, the optional extra `carl-spec[plot]`: imported only when a figure is drawn."""

from __future__ import annotations

from typing import Any


def pyplot(what: str) -> Any:
    """`matplotlib.pyplot` on the Agg backend (unless one was chosen), or an ImportError that says
    how to install it; `what` names the figure in that message."""
    try:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError(
            f"{what} needs matplotlib, which carl-spec does not install by itself: "
            "pip install 'carl-spec[plot]' (or pip install matplotlib). The JSON and Markdown need nothing more."
        ) from e
    return plt
