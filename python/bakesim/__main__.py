"""python3 -m bakesim sweep SCENE --set KEY=V1,V2,... [--scheduler local|ADDRESS]: bakesim.sweep
(the Python sweep on Dask) from a shell. The command line's `bakesim sweep` uses bakesim.dask_runs."""
import sys

from .sweep import main as sweep_main

if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] != "sweep":
        print("usage: python3 -m bakesim sweep SCENE --set KEY=V1,V2,... [--scheduler local|ADDRESS]",
              file=sys.stderr)
        sys.exit(2)
    sys.exit(sweep_main(sys.argv[2:]))
