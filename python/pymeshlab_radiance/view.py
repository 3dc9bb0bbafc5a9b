"""``python -m pymeshlab_radiance.view MODEL.glb``: the radiance viewer (``viewer/viewer.html``, one
WebGL2 page, no network) for a .glb written by the filter ``radiance_export_gltf``.

    python -m pymeshlab_radiance.view fit.glb                      # serve on loopback, open a browser
    python -m pymeshlab_radiance.view fit.glb --output fit.html    # standalone page, the .glb inside
    python -m pymeshlab_radiance.view fit.glb --screenshot fit.png --size 640x480 \\
        --look-at 0,0,3,0,0,0,0,1,0 --fov 40                        # one frame in headless Chromium

The camera of ``--look-at EYE,TARGET,UP --fov HFOV --size WxH`` is the one of the CPU renderer
(``render_radiance --look-at``, rad::PinholeCamera::lookAt: horizontal field of view in degrees,
principal point at the image centre), so that both render the same view.

``--screenshot`` serves the page on 127.0.0.1 to Debian's ``chromium`` (headless, software GL:
SwiftShader through ANGLE), which draws ``--frames`` frames, and posts the canvas back as a PNG with
the time of every frame (printed, ``--times-json`` writes them).
"""

import argparse
import base64
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import webbrowser

from .thumbnail import write_atomically

VIEWER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "viewer", "viewer.html")
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")


class ViewerError(RuntimeError):
    """A refusal: what is wrong and what to do."""


def _numbers(text, count, what):
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        values = []
    if len(values) != count:
        raise ViewerError(f"{what} needs {count} comma-separated numbers, got '{text}'")
    return values


def camera_from_arguments(look_at, fov):
    """The page's camera (eye, target, up, horizontal fov in degrees) or None for the default view."""
    if look_at is None:
        return None
    v = _numbers(look_at, 9, "--look-at EYE,TARGET,UP")
    if not 0 < fov < 179:
        raise ViewerError(f"--fov must lie in (0, 179) degrees, got {fov}")
    return {"eye": v[0:3], "target": v[3:6], "up": v[6:9], "fov": fov}


def parse_size(text):
    try:
        width, height = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise ViewerError(f"--size must be WIDTHxHEIGHT, e.g. 640x480, got '{text}'")
    if not (1 <= width <= 8192 and 1 <= height <= 8192):
        raise ViewerError(f"--size must lie in 1x1..8192x8192, got '{text}'")
    return width, height


def read_model(path):
    """The .glb's bytes after checking it is a binary glTF with our extension."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ViewerError(f"cannot read '{path}': {e.strerror}; give the .glb written by radiance_export_gltf")
    if len(data) < 20 or data[:4] != b"glTF":
        raise ViewerError(f"'{path}' is not a binary glTF file (.glb); export one with radiance_export_gltf")
    if b"RADIANCE_vertex_radiance_functions" not in data[20:20 + int.from_bytes(data[12:16], "little")]:
        raise ViewerError(f"'{path}' has no radiance functions (extension RADIANCE_vertex_radiance_functions); "
                          "export it with radiance_export_gltf")
    return data


def page(config, embedded_model=None):
    """The viewer page with `config` (and the model, base64, when standalone)."""
    with open(VIEWER, encoding="utf-8") as f:
        html = f.read()
    html = html.replace("/*CONFIG*/{}/*END*/", json.dumps(config), 1)
    if embedded_model is not None:
        block = ('<script id="model" type="application/octet-stream">' +
                 base64.b64encode(embedded_model).decode("ascii") + "</script>")
        html = html.replace("<!--MODEL-->", block, 1)
    return html


class _Server:
    """The page and the model on 127.0.0.1; POST /result receives the screenshot."""

    def __init__(self, html, model):
        self.result = None
        self.received = threading.Event()
        outer = self

        class Handler(http.server.BaseHTTPRequestHandler):
            def log_message(self, *args):
                pass

            def _send(self, body, kind):
                self.send_response(200)
                self.send_header("Content-Type", kind)
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def do_GET(self):
                if self.path in ("/", "/index.html"):
                    self._send(html.encode("utf-8"), "text/html; charset=utf-8")
                elif self.path == "/model.glb":
                    self._send(model, "model/gltf-binary")
                else:
                    self.send_error(404)

            def do_POST(self):
                length = int(self.headers.get("Content-Length", 0))
                outer.result = json.loads(self.rfile.read(length).decode("utf-8"))
                self._send(b"{}", "application/json")
                outer.received.set()

        self.httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/"
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)
        self.thread.start()

    def close(self):
        self.httpd.shutdown()
        self.httpd.server_close()


def find_chromium():
    for name in CHROMIUM_NAMES:
        path = shutil.which(name)
        if path:
            return path
    raise ViewerError("no Chromium found for --screenshot; install Debian's package 'chromium' "
                      "(scripts/setup.sh does) or write a page with --output and open it in a browser")


def screenshot(model, png_path, size, camera=None, exposure=1.0, mean_color=False, frames=1, timeout=300):
    """Renders `frames` frames of `model` (the .glb bytes) in headless Chromium; writes the last one to
    `png_path` (atomically) and returns the page's report (frame times in ms, renderer, counts)."""
    width, height = size
    config = {"width": width, "height": height, "exposure": exposure, "meanColor": mean_color,
              "frames": frames, "reportTo": "/result", "model": "/model.glb"}
    if camera:
        config["camera"] = camera
    server = _Server(page(config), model)
    profile = tempfile.mkdtemp(prefix="radiance-viewer-")
    command = [find_chromium(), "--headless=new", "--no-sandbox", "--disable-gpu-sandbox",
               "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
               "--ignore-gpu-blocklist", "--no-first-run", "--disable-extensions", "--mute-audio",
               f"--user-data-dir={profile}", f"--window-size={width},{height}",
               server.url]
    log = tempfile.TemporaryFile()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=log)
    try:
        deadline = time.monotonic() + timeout
        while not server.received.wait(0.5):
            if process.poll() is not None:  # Chromium ended without posting: say why
                log.seek(0)
                tail = log.read().decode("utf-8", "replace").strip().splitlines()[-5:]
                raise ViewerError(f"Chromium exited (status {process.returncode}) without a picture: "
                                  + " | ".join(tail))
            if time.monotonic() > deadline:
                raise ViewerError(f"Chromium sent no picture within {timeout} s; try a smaller --size or a simpler mesh")
    finally:
        process.terminate()
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        log.close()
        server.close()
        shutil.rmtree(profile, ignore_errors=True)
    result = server.result
    if "error" in result:
        raise ViewerError(f"the viewer failed in Chromium: {result['error']}")
    header = "data:image/png;base64,"
    if not result.get("png", "").startswith(header):
        raise ViewerError("Chromium returned no PNG")
    _write_atomically(png_path, base64.b64decode(result.pop("png")[len(header):]))
    return result


def _write_atomically(path, data):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ViewerError(f"the folder of '{path}' does not exist; create it or choose another path")
    write_atomically(path, data)


def serve(model, camera=None, open_browser=True):
    """Serves the viewer on 127.0.0.1 until interrupted."""
    config = {"model": "/model.glb"}
    if camera:
        config["camera"] = camera
    server = _Server(page(config), model)
    print(f"Radiance viewer at {server.url} (Ctrl+C to stop)", flush=True)
    if open_browser:
        webbrowser.open(server.url)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        pass
    finally:
        server.close()


def add_arguments(parser):
    parser.add_argument("model", help="a .glb written by radiance_export_gltf")
    parser.add_argument("--output", metavar="PAGE.html", help="write a standalone page (the model inside) and exit")
    parser.add_argument("--screenshot", metavar="PNG", help="render one frame in headless Chromium, write it, exit")
    parser.add_argument("--size", default="800x600", help="image size WIDTHxHEIGHT (--screenshot)")
    parser.add_argument("--look-at", metavar="EX,EY,EZ,TX,TY,TZ,UX,UY,UZ",
                        help="camera: eye, target and up vector (default: the whole mesh from +z)")
    parser.add_argument("--fov", type=float, default=40.0, help="horizontal field of view in degrees (with --look-at)")
    parser.add_argument("--exposure", type=float, default=1.0, help="linear scale before the sRGB encoding")
    parser.add_argument("--mean-color", action="store_true", help="show COLOR_0 (the mean colour) instead of the RF")
    parser.add_argument("--frames", type=int, default=1, help="frames drawn and timed (--screenshot)")
    parser.add_argument("--times-json", metavar="FILE", help="write the frame times and renderer as JSON (--screenshot)")
    parser.add_argument("--no-browser", action="store_true", help="serve without opening a browser")


def run(args):
    model = read_model(args.model)
    camera = camera_from_arguments(args.look_at, args.fov)
    if args.frames < 1:
        raise ViewerError(f"--frames must be at least 1, got {args.frames}")
    if args.output:
        config = {"exposure": args.exposure, "meanColor": args.mean_color}
        if camera:
            config["camera"] = camera
        _write_atomically(args.output, page(config, model).encode("utf-8"))
        print(f"wrote {args.output}")
        return 0
    if args.screenshot:
        result = screenshot(model, args.screenshot, parse_size(args.size), camera, args.exposure, args.mean_color,
                            args.frames)
        times = sorted(result["frameTimesMs"])
        print(f"wrote {args.screenshot}: {result['vertices']} vertices, {result['faces']} faces, "
              f"renderer {result['renderer']}, {len(times)} frames, median {times[len(times) // 2]:.1f} ms, "
              f"first {result['frameTimesMs'][0]:.1f} ms")
        if args.times_json:
            _write_atomically(args.times_json, json.dumps(result, indent=1).encode("utf-8"))
        return 0
    serve(model, camera, open_browser=not args.no_browser)
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pymeshlab_radiance.view", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(parser)
    args = parser.parse_args(argv)
    try:
        return run(args)
    except ViewerError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
