# SPDX-License-Identifier: MIT
"""HIMM, the histogramic in-motion map (J. Borenstein, Y. Koren, "Histogramic in-motion
mapping for mobile robot obstacle avoidance", IEEE Transactions on Robotics and Automation
7(4), 1991), as a second classic mapper beside the firmware's on the same sonar logs.

Each cell holds a certainty 0..15. A reading adds 3 to the one cell on the beam's axis at
the measured range and takes 1 from each cell the axis crosses on its way there; only the
axis counts, not the cone. A cell is occupied at `threshold` or more, free when a reading
touched it and it stayed below, else unknown. The geometry is octomap_replay's (the sonar
mounted on the robot, the beam's bearing from the servo angle, echoes under the minimum
range skipped, timeouts skipped, echoes beyond the maximum range free rays of that length
with no hit), so that the three mappers read the same readings the same way.
"""
import csv
import math

import numpy as np

from .errors import ToolError

INCREMENT = 3
DECREMENT = 1
CERTAINTY_MAX = 15


def himm_map(readings, grid, mount, poses="true", min_range=0.02, max_range=1.0,
             threshold=3):
    """The trinary map (0 occupied, 254 free, 205 unknown; first row the largest y) of a
    readings.csv. grid = (a, b, origin_x, origin_y, cell), m; mount = (x, y, yaw_deg)."""
    a, b, ox, oy, cell = grid
    mx, my, myaw = mount
    certainty = np.zeros((b, a), dtype=np.int16)
    touched = np.zeros((b, a), dtype=bool)
    step = cell / 2.0
    n = 1

    def reading(row):
        if row["status"] == "timeout":
            return
        r = float(row["range_m"])
        servo = float(row["servo_deg"])
        x, y, th = (float(row["%s_%s" % (poses, k)]) for k in ("x_m", "y_m", "th_rad"))
        if r < min_range:
            return
        c, s = math.cos(th), math.sin(th)
        sx = x + mx * c - my * s - ox
        sy = y + mx * s + my * c - oy
        bearing = th + math.radians(90.0 - servo + myaw)
        bc, bs = math.cos(bearing), math.sin(bearing)
        hit = None
        if r < max_range:
            hit = (int(math.floor((sy + r * bs) / cell)), int(math.floor((sx + r * bc) / cell)))
        last = None
        for k in range(int(min(r, max_range) / step) + 1):
            t = k * step
            at = (int(math.floor((sy + t * bs) / cell)), int(math.floor((sx + t * bc) / cell)))
            if at == last or at == hit or not (0 <= at[0] < b and 0 <= at[1] < a):
                continue
            last = at
            certainty[at] = max(certainty[at] - DECREMENT, 0)
            touched[at] = True
        if hit is not None and 0 <= hit[0] < b and 0 <= hit[1] < a:
            certainty[hit] = min(certainty[hit] + INCREMENT, CERTAINTY_MAX)
            touched[hit] = True

    try:
        with open(readings, newline="") as f:
            for n, row in enumerate(csv.DictReader(f), start=2):
                reading(row)
    except (KeyError, TypeError, ValueError):  # (UnicodeDecodeError is a ValueError)
        raise ToolError("%s: not a readings.csv (line %d)" % (readings, n)) from None
    except OSError as e:
        raise ToolError("%s: %s" % (readings, e.strerror)) from None
    img = np.full((b, a), 205, dtype=np.uint8)
    img[touched] = 254
    img[certainty >= threshold] = 0
    return img[::-1].copy()
