"""The source papers' timing tables, as ratios, beside ours from the same kind of run.

The papers measured absolute times on 2010-era GPUs; only ratios carry over
(frame time of a setting / frame time of MIP at one sample per voxel).
"""
from __future__ import annotations

from typing import Sequence

#: Analytic MIP paper, Table 2: seconds per frame, Radeon HD5670, 1200x1024.
AMIP_TABLE_2 = {
    "cenovix-ct1-abdomen 512x512x361": {"MIP 1x": 0.375, "MIP 4x": 1.225, "MIP 8x": 2.252, "AMIP": 0.654},
    "quanredeusix 384x22x512": {"MIP 1x": 0.106, "MIP 4x": 0.14, "MIP 8x": 0.188, "AMIP": 0.103},
    "felix-cemra-hires 576x118x576": {"MIP 1x": 0.131, "MIP 4x": 0.313, "MIP 8x": 0.62, "AMIP": 0.202},
    "mri 256x256x124": {"MIP 1x": 0.249, "MIP 4x": 0.72, "MIP 8x": 1.408, "AMIP": 0.335},
}

#: Our bench settings that correspond to the paper's columns.
_AMIP_COLUMNS = {"MIP 1x": "stock 1x", "MIP 4x": "stock 4x", "MIP 8x": "stock 8x", "AMIP": "analytic"}


def amip_table(rows: Sequence[dict]) -> str:
    """Markdown: time / MIP 1x for MIP 4x, MIP 8x and AMIP, the paper's rows then ours.

    Parameters
    ----------
    rows : sequence of dict
        Rows of ``mipcast bench`` (keys ``scene``, ``view``, ``size``,
        ``setting``, ``ratio_to_stock``, ``p99_pct``).

    Examples
    --------
    >>> rows = [{"scene": "s", "view": "v", "size": 8, "setting": name, "ratio_to_stock": r, "p99_pct": e}
    ...         for name, r, e in [("stock 1x", 1.0, 5.0), ("stock 4x", 3.0, 1.0),
    ...                            ("stock 8x", 6.0, 0.5), ("analytic", 3.5, 0.001)]]
    >>> print(amip_table(rows).splitlines()[-1])
    | mipcast, llvmpipe: s v 8² | 3.00 (p99 1%) | 6.00 (p99 0.5%) | 3.50 (p99 0.001%) |
    """
    lines = ["| data | MIP 4x / MIP 1x | MIP 8x / MIP 1x | AMIP / MIP 1x |", "| --- | --- | --- | --- |"]
    for name, times in AMIP_TABLE_2.items():
        base = times["MIP 1x"]
        lines.append(f"| paper, HD5670: {name} | " + " | ".join(
            f"{times[c] / base:.2f}" for c in ("MIP 4x", "MIP 8x", "AMIP")) + " |")
    panels = sorted({(r["scene"], r["view"], r["size"]) for r in rows})
    for scene, view, size in panels:
        found = {r["setting"]: r for r in rows if (r["scene"], r["view"], r["size"]) == (scene, view, size)}
        if not all(label in found for label in _AMIP_COLUMNS.values()):
            continue
        cells = [f"{found[_AMIP_COLUMNS[c]]['ratio_to_stock']:.2f} (p99 {found[_AMIP_COLUMNS[c]]['p99_pct']:.3g}%)"
                 for c in ("MIP 4x", "MIP 8x", "AMIP")]
        lines.append(f"| mipcast, llvmpipe: {scene} {view} {size}² | " + " | ".join(cells) + " |")
    return "\n".join(lines)
