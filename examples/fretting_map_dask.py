"""A fretting map on a Dask cluster: each (load, amplitude) point is one task calling the
extension; the result is identical to the serial map (and to `halfspace fretting-map`).

    python examples/fretting_map_dask.py                       # a LocalCluster of 2 workers
    python examples/fretting_map_dask.py tcp://scheduler:8786  # a running cluster's scheduler

The workers need this package installed (`pip install ./python` on each, or an image with it).
"""
import sys

import numpy as np

import halfspace as hs

CONFIG = {"grid": 32, "normal_steps": 10, "shift_step": 0.004e-6, "subsurface_over_a": 0.0}
LOADS = [0.04, 0.08, 0.16]                      # N
AMPLITUDES = [0.01e-6, 0.02e-6, 0.04e-6, 0.08e-6]  # m


def main(scheduler: str | None = None) -> None:
    from distributed import Client, LocalCluster

    if scheduler:
        client = Client(scheduler)  # type: ignore[no-untyped-call]
        cluster = None
    else:
        cluster = LocalCluster(  # type: ignore[no-untyped-call]
            n_workers=2, threads_per_worker=1, dashboard_address=None
        )
        client = Client(cluster)  # type: ignore[no-untyped-call]
    try:
        m = hs.fretting_map(LOADS, AMPLITUDES, config=CONFIG, client=client)
    finally:
        client.close()  # type: ignore[no-untyped-call]
        if cluster is not None:
            cluster.close()
    names = {0: "partial slip", 1: "mixed", 2: "gross slip"}
    for i, w in enumerate(LOADS):
        cells = ", ".join(f"{names[r]} {e:.2e} J" for r, e in zip(m.regime[i], m.dissipated_energy[i]))
        print(f"W = {w * 1e3:5.1f} mN: {cells}")
    serial = hs.fretting_map(LOADS, AMPLITUDES, config=CONFIG)
    assert np.array_equal(serial.dissipated_energy, m.dissipated_energy)
    print("identical to the serial map")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
