#!/usr/bin/env python3
"""Real photographs for the fit: OpenCV's chessboard samples as a calibrated MeshLab project.

The 26 photographs (left01..14 and right01..14 without 10, 640x480 greyscale, a stereo webcam pair
looking at a hand-held 9x6-corner chessboard) come from Debian's opencv-doc package through
samples/fetch_data.sh (checksums in samples/data.sha256; they are never committed). This script:

  1. finds the 9x6 inner corners in every photograph (cv2.findChessboardCorners, refined to
     sub-pixel accuracy by cv2.cornerSubPix);
  2. calibrates each camera of the pair on its own photographs (cv2.calibrateCamera: intrinsics,
     5 distortion coefficients, one board pose per photograph);
  3. undistorts every photograph (cv2.getOptimalNewCameraMatrix with alpha 0, so that no pixel of
     the result is invented) and writes it as an RGB PNG (MeshLab's rasters must be undistorted);
  4. writes the board as a planar triangle mesh (board.ply: the 10 x 7 squares, a vertex every
     `--step` squares, normal toward the cameras) in the board's frame (unit = one square), and
     project.mlp, a MeshLab project whose MLRaster cameras are the calibrated poses (the VCGCamera
     convention of common/io/meshlab_project.cpp: rotation rows right, up, backwards;
     TranslationVector = -centre; CenterPx from the left and from the bottom; pixel centres at
     +0.5, where OpenCV puts them at integers);
  5. writes calibration.json: the RMS reprojection error of each camera and what was used.

Usage: calibrate_chessboard.py --photos DIR --out DIR [--step 0.125]
Needs OpenCV's Python bindings (Debian: python3-opencv, installed by scripts/setup.sh).
"""
import argparse
import json
import os
import sys

import numpy as np

try:
    import cv2
except ImportError:  # pragma: no cover - reported to the user
    sys.exit("calibrate_chessboard.py needs OpenCV's Python bindings: apt-get install python3-opencv "
             "(or pip install opencv-python-headless in the environment running this script)")

CORNERS = (9, 6)  # inner corners of the board
NAMES = [f"{side}{i:02d}.jpg" for side in ("left", "right") for i in list(range(1, 10)) + list(range(11, 15))]
PIXEL_SIZE_MM = 0.01  # arbitrary: MeshLab's cameras need one; only focal / pixel size matters


def find_corners(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise SystemExit(f"cannot read {path}: run samples/fetch_data.sh first")
    found, corners = cv2.findChessboardCorners(image, CORNERS)
    if not found:
        return image, None
    criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)
    corners = cv2.cornerSubPix(image, corners, (11, 11), (-1, -1), criteria)
    return image, corners


def board_points():
    grid = np.zeros((CORNERS[0] * CORNERS[1], 3), np.float32)
    grid[:, :2] = np.mgrid[0:CORNERS[0], 0:CORNERS[1]].T.reshape(-1, 2)
    return grid


def write_board(path, step, normal_sign):
    """The squares of the board, [-1, 9] x [-1, 6] in corner units, z = 0."""
    nx = int(round(10 / step)) + 1
    ny = int(round(7 / step)) + 1
    xs = np.linspace(-1.0, 9.0, nx)
    ys = np.linspace(-1.0, 6.0, ny)
    vertices = [(x, y, 0.0) for y in ys for x in xs]
    faces = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i
            b, c, d = a + 1, a + nx + 1, a + nx
            # Counter-clockwise seen from the side the normal points to.
            faces.append((a, b, c) if normal_sign > 0 else (a, c, b))
            faces.append((a, c, d) if normal_sign > 0 else (a, d, c))
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in vertices:
            f.write(f"{v[0]:.6f} {v[1]:.6f} {v[2]:.6f} 0 0 {normal_sign:.1f}\n")
        for t in faces:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    return len(vertices)


def raster_xml(label, image_file, rotation, centre, camera_matrix, width, height):
    fx, fy = camera_matrix[0, 0], camera_matrix[1, 1]
    cx, cy = camera_matrix[0, 2] + 0.5, camera_matrix[1, 2] + 0.5  # OpenCV: pixel centres at integers
    vcg_rotation = rotation.copy()
    vcg_rotation[1] *= -1.0  # down -> up
    vcg_rotation[2] *= -1.0  # forward -> backwards
    focal_mm = fx * PIXEL_SIZE_MM
    matrix = " ".join(
        f"{vcg_rotation[i, j]:.9g}" if i < 3 and j < 3 else ("1" if i == j else "0") for i in range(4) for j in range(4))
    return (f'  <MLRaster label="{label}">\n'
            f'   <VCGCamera TranslationVector="{-centre[0]:.9g} {-centre[1]:.9g} {-centre[2]:.9g} 1" '
            f'LensDistortion="0 0" ViewportPx="{width} {height}" '
            f'PixelSizeMm="{PIXEL_SIZE_MM:.9g} {focal_mm / fy:.9g}" CenterPx="{cx:.9g} {height - cy:.9g}" '
            f'FocalMm="{focal_mm:.9g}" RotationMatrix="{matrix} " CameraType="0" BinaryData="0"/>\n'
            f'   <Plane semantic="1" fileName="{image_file}"/>\n  </MLRaster>\n')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--photos", required=True, help="folder with left01.jpg .. right14.jpg")
    parser.add_argument("--out", required=True, help="output folder (created)")
    parser.add_argument("--step", type=float, default=0.125, help="mesh spacing in squares (default 0.125)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    objp = board_points()
    rasters, report = [], {"cameras": {}, "photographs": []}
    centres = []
    for side in ("left", "right"):
        names = [n for n in NAMES if n.startswith(side)]
        images, found_names, image_points = {}, [], []
        for name in names:
            image, corners = find_corners(os.path.join(args.photos, name))
            images[name] = image
            if corners is None:
                print(f"{name}: chessboard not found, skipped")
                continue
            found_names.append(name)
            image_points.append(corners)
        if len(found_names) < 3:
            raise SystemExit(f"only {len(found_names)} {side} photographs show the chessboard: cannot calibrate")
        height, width = images[found_names[0]].shape
        rms, matrix, distortion, rvecs, tvecs = cv2.calibrateCamera(
            [objp] * len(found_names), image_points, (width, height), None, None)
        new_matrix, _ = cv2.getOptimalNewCameraMatrix(matrix, distortion, (width, height), 0.0)
        report["cameras"][side] = dict(rms_reprojection_px=float(rms), photographs=len(found_names),
                                       matrix=matrix.tolist(), distortion=distortion.ravel().tolist(),
                                       undistorted_matrix=new_matrix.tolist())
        print(f"{side} camera: {len(found_names)} photographs, RMS reprojection error {rms:.3f} px")
        for name, rvec, tvec in zip(found_names, rvecs, tvecs):
            undistorted = cv2.undistort(images[name], matrix, distortion, None, new_matrix)
            png = name.replace(".jpg", ".png")
            cv2.imwrite(os.path.join(args.out, png), cv2.cvtColor(undistorted, cv2.COLOR_GRAY2BGR))
            rotation, _ = cv2.Rodrigues(rvec)
            centre = (-rotation.T @ tvec).ravel()
            centres.append(centre)
            rasters.append(raster_xml(name[:-4], png, rotation, centre, new_matrix, width, height))
            report["photographs"].append(dict(name=name, centre=centre.tolist()))

    # The board's normal points toward the cameras (all on one side of the board).
    normal_sign = 1.0 if np.mean([c[2] for c in centres]) > 0 else -1.0
    if any(np.sign(c[2]) != normal_sign for c in centres):
        raise SystemExit("the calibrated cameras are on both sides of the board: the calibration failed")
    vertices = write_board(os.path.join(args.out, "board.ply"), args.step, normal_sign)
    with open(os.path.join(args.out, "project.mlp"), "w") as f:
        f.write("<!DOCTYPE MeshLabDocument>\n<MeshLabProject>\n <MeshGroup/>\n <RasterGroup>\n")
        f.writelines(rasters)
        f.write(" </RasterGroup>\n</MeshLabProject>\n")
    report.update(vertices=vertices, step=args.step, normal_sign=normal_sign)
    with open(os.path.join(args.out, "calibration.json"), "w") as f:
        json.dump(report, f, indent=1)
    print(f"wrote {len(rasters)} rasters, board.ply ({vertices} vertices), project.mlp in {args.out}")


if __name__ == "__main__":
    main()
