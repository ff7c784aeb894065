"""Lap lengths `split_laps` finds on the fixed-chain hug wraps, against the generator's.

The wraps of ``bench_recognition.py --only fixed-chain`` (64 links, 1.2-2
laps, offset 0-2, seed 0), clean and with noise. A noisy wrap is its clean
wrap plus joint noise, so each wrap's true lap length is read from the clean
chain: the length ``P`` (within 20 % of ``(n - approach) / laps``) at which
its last joint comes back closest to the point ``P`` links before it. Wraps
where that point is more than half a link off are left out. Prints, per
noise level, how many lap lengths are within 6 % of the truth, how many wraps
get a lap about as long as the whole chain (laps < 1.12 found where the
generator wrapped 1.2 or more) and lists the wrong ones with ``--list``.

Usage (from the repository root)::

    PYTHONPATH=src python benchmarks/lap_periods.py --noises 0,0.05 [--list]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from tentaclass.datasets import mpeg7_tentacle
from tentaclass.features import split_laps
from tentaclass.wrapping import grasp_state

MPEG7 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7-part-b"


def _wraps(noise: float):
    return mpeg7_tentacle(MPEG7, 64, "hug", protocol="fixed-chain", laps=(1.2, 2.0),
                          offset=(0.0, 2.0), noise=noise, random_state=0)  # fmt: skip


def true_periods(clean) -> tuple[np.ndarray, np.ndarray]:
    """Links per lap of each clean wrap and how far its end then lies from its own path."""
    q = np.nan_to_num(clean.data)
    g = grasp_state(q)
    heading = np.cumsum(q * g.direction[:, None], axis=1)
    n = q.shape[1]
    z = np.concatenate([np.zeros((len(q), 1)), np.cumsum(np.exp(1j * heading), axis=1)], axis=1)
    guess = (n - g.offset_links) / clean.laps
    cands = np.arange(3.0, n + 0.05, 0.1)
    period, gap = np.full(len(q), np.nan), np.full(len(q), np.inf)
    for r in range(len(q)):
        p = cands[np.abs(cands - guess[r]) <= 0.2 * guess[r]]
        if p.size == 0:
            continue
        x = n - p
        before = np.interp(x, np.arange(n + 1), z[r].real) + 1j * np.interp(x, np.arange(n + 1),
                                                                           z[r].imag)  # fmt: skip
        d = np.abs(z[r, -1] - before)
        period[r], gap[r] = p[np.argmin(d)], d.min()
    return period, gap


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--noises", default="0,0.05")
    parser.add_argument("--list", action="store_true", help="list the wrong wraps")
    a = parser.parse_args()
    clean = _wraps(0.0)
    truth, gap = true_periods(clean)
    known = gap < 0.5
    for noise in (float(x) for x in a.noises.split(",")):
        d = clean if noise == 0 else _wraps(noise)
        s = split_laps(d.data)
        right = np.abs(s.period - truth) <= 0.06 * truth
        whole = s.closed & (s.laps < 1.12) & (clean.laps > 1.19)
        print(f"noise {noise:g}: lap length within 6 % of the truth {np.sum(right & known)} / "
              f"{known.sum()}, a lap about the whole chain {whole.sum()}, no lap "
              f"{np.sum(~s.closed)}")  # fmt: skip
        if a.list:
            for i in np.flatnonzero(known & ~right):
                print(f"  {d.names[i]:24s} laps {clean.laps[i]:.2f}, lap {truth[i]:5.1f} links; "
                      f"found {s.period[i]:5.1f} ({s.laps[i]:.2f} laps)")  # fmt: skip


if __name__ == "__main__":
    main()
