#!/usr/bin/env python3
"""make_view_file.py OUT.txt --bbox XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX [options]

Writes a decoration view file (docs/decorate-radiance.md) for the view MeshLab 2020.09 shows after
loading a mesh or resetting the trackball (src/meshlab/glarea.cpp: resetTrackBall, setView):
  modelview  = gluLookAt(0, 0, d, 0, 0, 0, 0, 1, 0) * Scale(3 / bbox diagonal) * Translate(-bbox centre)
  projection = gluPerspective(fov, W / H, 0.1 d, d + 1.75 ...)   with d = 1.75 / tan(fov / 2)
computed here from the OpenGL manual pages, independently of camera/gl_view_camera.cpp. For the
dry runs of the GUI tests (decoration_tools_dry_run.sh): no MeshLab needed.
Options: --widget-origin GX,GY [0,0]  --widget-size W,H [1000,700]  --viewport X,Y,W,H [0,0,widget]
         --fov DEG [60]  --mode per-fragment  --exposure 0  --tonemap clamp  --frame 1
         --yaw DEG [0] (extra trackball rotation about the vertical axis)"""
import argparse
import math


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def translate(x, y, z):
    return [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]


def scale(s):
    return [[s, 0, 0, 0], [0, s, 0, 0], [0, 0, s, 0], [0, 0, 0, 1]]


def rotate_y(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]]


def perspective(fovy, aspect, near, far):
    f = 1.0 / math.tan(math.radians(fovy) / 2)
    return [[f / aspect, 0, 0, 0], [0, f, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]]


def column_major(m):
    return [m[i][j] for j in range(4) for i in range(4)]


def numbers(text, n):
    values = [float(v) for v in text.split(",")]
    if len(values) != n:
        raise SystemExit(f"expected {n} numbers, got '{text}'")
    return values


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out")
    p.add_argument("--bbox", required=True)
    p.add_argument("--widget-origin", default="0,0")
    p.add_argument("--widget-size", default="1000,700")
    p.add_argument("--viewport")
    p.add_argument("--fov", type=float, default=60.0)
    p.add_argument("--yaw", type=float, default=0.0)
    p.add_argument("--mode", default="per-fragment")
    p.add_argument("--exposure", default="0")
    p.add_argument("--tonemap", default="clamp")
    p.add_argument("--frame", default="1")
    a = p.parse_args()
    b = numbers(a.bbox, 6)
    gx, gy = numbers(a.widget_origin, 2)
    ww, wh = numbers(a.widget_size, 2)
    vp = numbers(a.viewport, 4) if a.viewport else [0, 0, ww, wh]
    centre = [(b[i] + b[i + 3]) / 2 for i in range(3)]
    diag = math.sqrt(sum((b[i + 3] - b[i]) ** 2 for i in range(3)))
    d = 1.75 / math.tan(math.radians(a.fov / 2))
    mv = matmul(translate(0, 0, -d),
                matmul(rotate_y(a.yaw), matmul(scale(3.0 / diag), translate(-centre[0], -centre[1], -centre[2]))))
    pr = perspective(a.fov, vp[2] / vp[3], 0.1 * d, d + 1.75 + 3.0)
    with open(a.out, "w") as f:
        f.write("radiance-decoration-view 1\n")
        f.write(f"frame {a.frame}\nmode {a.mode}\n")
        f.write("viewport " + " ".join(str(int(v)) for v in vp) + "\n")
        f.write(f"widget_origin {int(gx)} {int(gy)}\nwidget_size {int(ww)} {int(wh)}\ndevice_pixel_ratio 1\n")
        f.write("modelview " + " ".join(repr(v) for v in column_major(mv)) + "\n")
        f.write("projection " + " ".join(repr(v) for v in column_major(pr)) + "\n")
        f.write(f"exposure {a.exposure}\ntonemap {a.tonemap}\n")


if __name__ == "__main__":
    main()
