# %% [markdown]
# # From a PX4 flight log to a noise model and a PX4 temperature calibration
#
# A notebook in the percent format (`# %%` cells: Jupyter with jupytext, VS Code,
# Spyder), also run whole as a plain script by `.ci/run`:
#
#     python docs/notebook_example.py [LOG.ulg] [--out DIR]
#
# It reads a PX4 ULog, plots the gyro's overlapping Allan deviation with its
# intervals, reads the IEEE Std 952 noise terms off it, and fits and exports a
# temperature compensation for PX4 from a chamber run. Needs `imutherm`,
# matplotlib and pandas: `pip install './crates/python[notebook]'`.

# %%
import argparse
import pathlib
import sys

import matplotlib

if "ipykernel" not in sys.modules:
    matplotlib.use("Agg")  # as a script: files, no window
import matplotlib.pyplot as plt
import numpy as np

import imutherm

HERE = pathlib.Path(__file__).resolve().parent
SAMPLE = HERE.parent / "crates" / "robotlogs" / "tests" / "fixtures" / "px4" / "sample_log_small.ulg"
parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("log", nargs="?", default=SAMPLE, type=pathlib.Path, help="a PX4 ULog")
parser.add_argument("--out", default=pathlib.Path("notebook_example_out"), type=pathlib.Path)
args = parser.parse_args([] if "ipykernel" in sys.modules else None)
args.out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## Read the log
# The accelerometer and gyro of the chosen IMU stream, on the clock of its
# message stamps; a time gap in the log is a run of NaN rows, with the real
# stamps beside them.

# %%
rec = imutherm.read(args.log)
print(rec)
frame = rec.to_pandas()
print(frame[["gyro_x", "timestamp_s"]].head())
print(f"{frame['gyro_x'].isna().sum()} empty slots in {len(frame)}")

# %% [markdown]
# ## OADEV with its intervals
# The gaps are skipped term by term (with a warning). `lo` and `hi` bound each
# point at 68.3 % from the noise identified at that tau (Greenhall's EDF).

# %%
curve = imutherm.oadev(rec.channels["gyro_x"], rate=rec.rate, taus="octave")
fig, ax = plt.subplots()
ax.errorbar(curve.taus, curve.devs, yerr=[curve.devs - curve.lo, curve.hi - curve.devs], fmt="o-",
            capsize=3, label="gyro_x")
ax.set(xscale="log", yscale="log", xlabel="tau [s]", ylabel=f"OADEV [{rec.units['gyro_x']}]",
       title=rec.file.split("/")[-1])
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(args.out / "oadev.png", dpi=120)
print(curve.to_pandas()[["devs", "lo", "hi", "noise_id"]])

# %% [markdown]
# ## The noise model
# The IEEE Std 952 terms read off the curve, each with how it was read: a fit
# with its 95 % interval, a slope, or an upper bound when the log is too short
# to show the term.

# %%
terms = imutherm.noise_terms(rec.channels["gyro_x"], rate=rec.rate)["terms"]
for name, term in terms.items():
    value = "-" if term["value"] is None else f"{term['value']:.3e}"
    print(f"{name:<18} {term['symbol']:<4} {value:>10}  ({term['how']})")

# %% [markdown]
# ## A temperature compensation for PX4
# A flight is too short and too steady in temperature to fit one: the model
# comes from a chamber run, here imutherm's simulation of an MPU-9250 cooling
# from 60 to 20 degrees C (with a real sensor, the recording of its own run).
# The model is fitted as PX4 evaluates it (a cubic at most) and exported as its
# TC_G* / TC_A* parameters.

# %%
chamber = imutherm.simulate(preset="mpu9250-thesis", duration=1800, rate=20,
                            profile="cooling:60:20:1800", seed=3)
run = args.out / "chamber_run.csv"
with open(run, "w") as f:
    f.write(f"# sample_rate_hz: {chamber.rate}\n{','.join(chamber.channels)}\n")
    np.savetxt(f, np.column_stack(list(chamber.channels.values())), delimiter=",")
model = imutherm.tcal_fit([run], firmware="px4")
print(f"fitted {model.t_min:.1f} to {model.t_max:.1f} degrees C, reference {model.t_ref:.1f}")
params = model.export("px4")
(args.out / "tcal_px4.params").write_text(params)
print(params.splitlines()[0])
print(f"{len(params.splitlines())} lines written to {args.out / 'tcal_px4.params'}")
