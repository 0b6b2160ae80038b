"""Module-level pieces of tests/test_sweep_dask.py that Dask workers (other processes)
import by name: the sweep's scene and points, measures that slow a sweep down or kill the
worker running them once, and a driver that runs the sweep on its own LocalCluster."""

import dataclasses
import os
import signal
import time

import numpy as np

import tendonrod as tr
from tendonrod.sweeps import tip_measure


def args(n=24):
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    base = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.0],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.0, 0.0))],
    )
    forces = [(-f, 0.0, 0.0) for f in np.linspace(0.05, 1.2, n)]
    return base, {"loads[0].force": forces}


def slow_measure(scene, sol):
    time.sleep(0.2)  # slows the sweep so that the test can kill its driver half way
    return tip_measure(scene, sol)


@dataclasses.dataclass(frozen=True)
class KillOnce:
    """A measure that kills the worker process running it (SIGKILL, no cleanup), the
    first time it sees the load ``fx``: it writes its pid to ``marker`` first, and does
    not kill again once the marker exists."""

    marker: str
    fx: float

    def __call__(self, scene, sol):
        if scene.loads[0].force[0] == self.fx and not os.path.exists(self.marker):
            with open(self.marker, "w") as fh:
                fh.write(str(os.getpid()))
                fh.flush()
                os.fsync(fh.fileno())
            os.kill(os.getpid(), signal.SIGKILL)
        return tip_measure(scene, sol)


def cluster():
    """A LocalCluster of two single-threaded worker processes (its dashboard on a free port)."""
    from dask.distributed import LocalCluster

    return LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")


def drive(path):
    """The driver: the slow sweep on its own LocalCluster, recorded to ``path``."""
    from dask.distributed import Client

    base, vary = args()
    with cluster() as c, Client(c) as client:
        return tr.sweep(
            base,
            vary,
            grid=False,
            chunksize=2,
            measure=slow_measure,
            executor=client.get_executor(),
            file=path,
            progress=False,
        )
