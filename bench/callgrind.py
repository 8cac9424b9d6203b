"""The command prefix that runs Blender under callgrind, counting only the engine's render loop.

    from callgrind import callgrind_wrapper
    run = render_smis(blend, settings, threads=1, wrapper=callgrind_wrapper())

Blender links libhwy, whose static initialiser executes RDTSCP, an instruction valgrind 3.19 cannot
decode (SIGILL before Blender starts) on CPUs that have it. When libhwy is present the wrapper
preloads tools/hwy_timer_shim.cpp (compiled once into bench/results/), which replaces libhwy's timer
queries; the engine's code and its instruction counts are untouched."""
import glob
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
SHIM_SOURCE = os.path.join(HERE, "tools", "hwy_timer_shim.cpp")
SHIM = os.path.join(HERE, "results", "libhwy_timer_shim.so")
RENDER_LOOP = "smis::RenderSession::render_loop*"


def _shim():
    if not glob.glob("/usr/lib/*/libhwy.so*"):
        return None
    if not os.path.exists(SHIM) or os.path.getmtime(SHIM) < os.path.getmtime(SHIM_SOURCE):
        os.makedirs(os.path.dirname(SHIM), exist_ok=True)
        subprocess.run(["g++", "-O2", "-shared", "-fPIC", SHIM_SOURCE, "-o", SHIM], check=True)
    return SHIM


def callgrind_wrapper(out_file="/dev/null", collect=RENDER_LOOP, extra=()):
    """`env LD_PRELOAD=shim valgrind --tool=callgrind ...`: valgrind hands LD_PRELOAD on to Blender."""
    cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out_file, "--collect-atstart=no",
           "--toggle-collect=" + collect] + list(extra)
    shim = _shim()
    return (["env", "LD_PRELOAD=" + shim] if shim else []) + cmd
