#!/usr/bin/env python3
"""Per-leg breakdown of a `labodrone-bench sim face-follow --out DIR` CSV (the face-follow metric).

Re-computes the followable walking ticks as sim_commands.cpp does (the true face moves more than
0.1 m/s; the place face_distance_m in front of it inside the geofence), from the measured window
(5 s after the stage first reads "3 face-follow", then --walk seconds), and splits them into legs
(runs of ticks walking the same way). Per leg: time, ticks, the share of the run's squared distance
error, distance and centre RMS, the face tracked fraction, and the mean signed distance error.
With --trace T0 T1: every 5th tick in [T0, T1] (drone, set point, face, errors, stage). With --jumps:
the ticks after 30 s where the drone's estimate moved more than 0.02 m beyond what its velocity
explains (estimator corrections).

usage: face_follow_legs.py CSV [--walk 30] [--room xmin ymin xmax ymax] [--margin 0.3] [--trace T0 T1] [--jumps]
"""
import argparse
import csv
import math

FX, FY, CX, CY, W, H = 569.9, 568.0, 331.4, 135.9, 640, 360  # config/default.json cameras.front


def centre_fraction(x, y, z):
    if z <= 0.1:
        return 1.0
    u, v = FX * x / z + CX, FY * y / z + CY
    return math.hypot(u - 0.5 * W, v - 0.5 * H) / W


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--walk", type=float, default=30.0)
    ap.add_argument("--room", type=float, nargs=4, default=[-1.5, -3.0, 6.5, 3.0])
    ap.add_argument("--margin", type=float, default=0.3)
    ap.add_argument("--distance", type=float, default=1.0)
    ap.add_argument("--trace", type=float, nargs=2)
    ap.add_argument("--jumps", action="store_true")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    found = next(float(r["t_s"]) for r in rows if r["stage"] == "3 face-follow")
    start, end = found + 5.0, found + 5.0 + a.walk
    xmin, ymin, xmax, ymax = a.room
    legs, last, total = [], None, 0.0
    for r in rows:
        t = float(r["t_s"])
        if t <= start or t > end + 1e-9 or r["face_x_m"] == "":
            continue
        fx, fy = float(r["face_x_m"]), float(r["face_y_m"])
        prev, last = last, (t, fx, fy)
        if prev is None:
            continue
        dt = t - prev[0]
        sx, sy = fx - prev[1], fy - prev[2]
        if math.hypot(sx, sy) <= 0.1 * dt:
            continue
        n = math.hypot(sx, sy)
        ax, ay = fx + a.distance * sx / n, fy + a.distance * sy / n
        if not (xmin + a.margin <= ax <= xmax - a.margin and ymin + a.margin <= ay <= ymax - a.margin):
            continue
        z = float(r["face_cam_z_m"])
        de = z - a.distance
        ce = centre_fraction(float(r["face_cam_x_m"]), float(r["face_cam_y_m"]), z)
        direction = round(math.degrees(math.atan2(sy, sx)) / 90.0) % 4
        if not legs or legs[-1]["dir"] != direction or t - legs[-1]["t1"] > 0.5:
            legs.append({"dir": direction, "t0": t, "t1": t, "d": [], "c": [], "tracked": 0})
        leg = legs[-1]
        leg["t1"] = t
        leg["d"].append(de)
        leg["c"].append(ce)
        leg["tracked"] += r["target"] == "tracking"
        total += de * de
    names = {0: "+x", 1: "+y", 2: "-x", 3: "-y"}
    n_all = sum(len(l["d"]) for l in legs)
    print(f"window {start:.2f}-{end:.2f} s, followable ticks {n_all}")
    print("leg  from    to      ticks  share  dist_rms  mean_d  centre_rms  tracked")
    dd, cc = [], []
    for l in legs:
        d, c = l["d"], l["c"]
        dd += d
        cc += c
        rms = lambda v: math.sqrt(sum(x * x for x in v) / len(v))
        print(f"{names[l['dir']]:>3}  {l['t0']:6.2f}  {l['t1']:6.2f}  {len(d):5d}  {sum(x*x for x in d)/max(total,1e-12):5.2f}"
              f"  {rms(d):8.3f}  {sum(d)/len(d):+6.3f}  {rms(c):10.3f}  {l['tracked']/len(d):6.1%}")
    if dd:
        print(f"all: distance RMS {math.sqrt(sum(x*x for x in dd)/len(dd)):.3f} m, centre RMS {math.sqrt(sum(x*x for x in cc)/len(cc)):.3f}")
    if a.jumps:
        num = lambda r, k: float(r[k]) if r[k] != "" else float("nan")
        for p, q in zip(rows, rows[1:]):
            t, dt = num(q, "t_s"), num(q, "t_s") - num(p, "t_s")
            jx = num(q, "est_x_m") - num(p, "est_x_m") - 0.5 * (num(p, "est_vx_mps") + num(q, "est_vx_mps")) * dt
            jy = num(q, "est_y_m") - num(p, "est_y_m") - 0.5 * (num(p, "est_vy_mps") + num(q, "est_vy_mps")) * dt
            if t > 30 and math.hypot(jx, jy) > 0.02:
                print(f"estimate jump at {t:.2f} s: {math.hypot(jx, jy):.3f} m ({q['source']})")
    if a.trace:
        print("t  drone(x,y,yaw)  des(x,y,yaw)  face(x,y,heading)  cam_z  cam_x  target  stage")
        for i, r in enumerate(rows):
            t = float(r["t_s"])
            if a.trace[0] <= t <= a.trace[1] and i % 5 == 0:
                g = lambda k: float(r[k]) if r[k] != "" else float("nan")
                print(f"{t:6.2f}  {g('true_x_m'):5.2f} {g('true_y_m'):5.2f} {g('true_yaw_rad'):5.2f}  "
                      f"{g('des_x_m'):5.2f} {g('des_y_m'):5.2f} {g('des_yaw_rad'):5.2f}  "
                      f"{g('face_x_m'):5.2f} {g('face_y_m'):5.2f} {g('face_heading_rad'):5.2f}  "
                      f"{g('face_cam_z_m'):5.2f} {g('face_cam_x_m'):5.2f}  {r['target']:<9} {r['stage']}")


if __name__ == "__main__":
    main()
