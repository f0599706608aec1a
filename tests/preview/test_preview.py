#!/usr/bin/python3
"""The live preview (`nori --preview`) driven in a real headless browser.

Usage: test_preview.py NORI WORKDIR

Debian's chromium, chromium-driver and python3-selenium (scripts/install-deps.sh --test)
must be installed: a missing one fails the test, it never skips. Run by ctest as
`preview.browser`. Checks, each printed as it passes:
  1. the server: 404 for any other path, 403 for a foreign Host or a /stop without its
     header, listening on 127.0.0.1 only (from /proc/net/tcp), a busy port a clear error;
  2. a render watched in the browser: the first pass's screenshot is the image (it
     matches the final PNG within the noise of one pass), the exposure slider changes the
     picture by its factor, Stop writes the _partial outputs and nori exits with 130;
  3. --preview-wait: the final image on the page equals the PNG nori wrote (tonemapping
     in the page and in nori agree to one 8-bit level), nori keeps serving until Close;
  4. a resumed render (nori --resume after a Ctrl-C): the page's first pass shows the
     samples and the time of the interrupted run as done, not a fresh start;
  5. a test file: its χ² pictures are served as they are written.
"""
import json
import os
import re
import signal
import shutil
import socket
import struct
import subprocess
import sys
import time
import urllib.error
import urllib.request
import zlib

NORI, WORKDIR = sys.argv[1], sys.argv[2]
os.makedirs(WORKDIR, exist_ok=True)

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select, WebDriverWait
except ImportError as error:
    sys.exit(f"FAIL: {error}: install python3-selenium (scripts/install-deps.sh --test)")
for tool in ("/usr/bin/chromium", "/usr/bin/chromedriver"):
    if not os.path.exists(tool):
        sys.exit(f"FAIL: {tool} is missing: install chromium and chromium-driver "
                 "(scripts/install-deps.sh --test)")

# A sphere on a floor lit by one point light (the `simple` integrator): every pixel away
# from an edge is the same at 1 spp as at 1000 up to the shading's change across the
# pixel, so a first pass can be compared with the final image. Brightest pixel ~0.55, so
# no channel saturates and the exposure slider scales every pixel.
SCENE = """<?xml version="1.0"?>
<scene>
    <integrator type="simple">
        <point name="position" value="2, 4, 3"/>
        <color name="energy" value="180, 160, 140"/>
    </integrator>
    <sampler type="independent">
        <integer name="sampleCount" value="$spp"/>
    </sampler>
    <camera type="perspective">
        <integer name="width" value="160"/>
        <integer name="height" value="120"/>
        <float name="fov" value="40"/>
        <transform name="toWorld">
            <lookat origin="0, 2, 7" target="0, 0.6, 0" up="0, 1, 0"/>
        </transform>
    </camera>
    <mesh type="sphere">
        <point name="center" value="0, -1000, 0"/>
        <float name="radius" value="1000"/>
    </mesh>
    <mesh type="sphere">
        <point name="center" value="0, 1, 0"/>
        <float name="radius" value="1"/>
    </mesh>
</scene>
"""
SCENE_FILE = os.path.join(WORKDIR, "preview.xml")
with open(SCENE_FILE, "w") as f:
    f.write(SCENE)


def check(condition, message):
    if not condition:
        sys.exit(f"FAIL: {message}")
    print(f"ok: {message}", flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_nori(*args, name):
    """Starts nori with args; returns (process, url, log file) once it serves."""
    log = os.path.join(WORKDIR, name + ".log")
    process = subprocess.Popen([NORI, "--no-progress", *args], stdout=subprocess.DEVNULL,
                               stderr=open(log, "w"))
    deadline = time.time() + 60
    while time.time() < deadline:
        text = open(log).read()
        for line in text.splitlines():
            if line.startswith("Preview: http://"):
                return process, line.split()[1], log
        if process.poll() is not None:
            sys.exit(f"FAIL: nori exited with {process.returncode} before serving:\n{text}")
        time.sleep(0.05)
    process.kill()
    sys.exit(f"FAIL: nori did not print its preview address within 60 s:\n{open(log).read()}")


def request(url, method="GET", headers=None):
    """(status, body) of an HTTP request; errors are statuses, not exceptions."""
    req = urllib.request.Request(url, method=method, headers=headers or {},
                                 data=b"" if method == "POST" else None)
    try:
        with urllib.request.urlopen(req, timeout=10) as response:
            return response.status, response.read()
    except urllib.error.HTTPError as error:
        return error.code, error.read()


def decode_png(data):
    """(width, height, rows of RGB tuples) of an 8-bit RGB or RGBA non-interlaced PNG."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    offset, idat = 8, b""
    while offset < len(data):
        length, kind = struct.unpack(">I4s", data[offset:offset + 8])
        body = data[offset + 8:offset + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, "unsupported PNG"
        elif kind == b"IDAT":
            idat += body
        offset += 12 + length
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):  # the five PNG filters (PNG spec. §9.2)
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                predictor = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[i] = (line[i] + predictor) & 0xFF
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows


def srgb_to_linear(level):
    v = level / 255
    return v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4


def pixels(rows):
    return [channel for row in rows for pixel in row for channel in pixel]


def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--force-device-scale-factor=1",
                     "--window-size=900,800",
                     "--user-data-dir=" + os.path.join(WORKDIR, "chromium-profile")):
        options.add_argument(argument)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def wait_for(driver, predicate, what, seconds=60):
    try:
        WebDriverWait(driver, seconds, poll_frequency=0.1).until(lambda d: predicate(d))
    except Exception:
        sys.exit(f"FAIL: timed out after {seconds} s waiting for {what}; the page says: "
                 f"{driver.find_element(By.ID, 'status').text!r}")


def body_data(driver, key):
    return driver.execute_script(f"return document.body.dataset.{key};")


def canvas_shot(driver):
    return decode_png(driver.find_element(By.ID, "image").screenshot_as_png)


def check_server_contract(url, port):
    status, _ = request(url + "etc/passwd")
    check(status == 404, f"GET /etc/passwd is a 404 (got {status})")
    status, _ = request(url + "image/../status")
    check(status in (400, 404), f"GET /image/../status is not served (got {status})")
    status, _ = request(url + "status", method="POST")
    check(status == 404, f"POST /status is a 404 (got {status})")
    status, _ = request(url, headers={"Host": "attacker.example:%d" % port})
    check(status == 403, f"a request with a foreign Host is refused (got {status})")
    status, _ = request(url + "stop", method="POST")
    check(status == 403, f"POST /stop without its header is refused (got {status})")
    status, _ = request(url + "image?layer=nonexistent")
    check(status == 404, f"an unknown layer is a 404 (got {status})")
    # /proc/net/tcp lists listening sockets (state 0A) as hex address:port.
    listening = []
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in open(table).read().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            if state == "0A" and int(local.split(":")[1], 16) == port:
                listening.append(local.split(":")[0])
    check(listening == ["0100007F"], f"port {port} listens on 127.0.0.1 only ({listening})")


def check_busy_port():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = subprocess.run([NORI, "--preview", str(port), SCENE_FILE],
                                capture_output=True, text=True, timeout=60)
    check(result.returncode == 1 and f"127.0.0.1:{port}" in result.stderr
          and "--preview" in result.stderr,
          f"a busy port is a clear error: {result.stderr.strip()!r}")


def check_render_stopped_from_page(driver):
    port = free_port()
    stem = os.path.join(WORKDIR, "stopped")
    nori, url, log = start_nori("--preview", str(port), "-D", "spp=1000000", "-o", stem,
                                SCENE_FILE, name="stopped")
    check_server_contract(url, port)
    driver.get(url)
    wait_for(driver, lambda d: int(body_data(d, "drawnFrame") or 0) >= 1, "the first pass")
    frame = int(body_data(driver, "drawnFrame"))
    width, height, first = canvas_shot(driver)
    check((width, height) == (160, 120), f"the canvas shows the 160x120 image ({width}x{height})")
    lit = sum(1 for value in pixels(first) if value > 10) / (3 * width * height)
    check(lit > 0.5, f"the screenshot of pass {frame} is not black ({lit:.0%} of values > 10)")

    # Two steps left of the middle: exposure -1 stop, a factor 1/2 on every linear value.
    slider = driver.find_element(By.ID, "exposure")
    slider.click()
    slider.send_keys(Keys.ARROW_LEFT, Keys.ARROW_LEFT)
    wait_for(driver, lambda d: body_data(d, "drawnExposure") == "-1", "exposure -1")
    _, _, darker = canvas_shot(driver)
    before = sum(srgb_to_linear(v) for v in pixels(first) if 20 < v < 250)
    after = sum(srgb_to_linear(v) for a, v in zip(pixels(first), pixels(darker)) if 20 < a < 250)
    check(abs(after / before - 0.5) < 0.03,
          f"exposure -1 halves the picture's linear values (ratio {after / before:.3f})")

    driver.find_element(By.ID, "stop").click()
    try:
        status = nori.wait(timeout=60)
    except subprocess.TimeoutExpired:
        nori.kill()
        sys.exit("FAIL: nori did not exit within 60 s of Stop")
    check(status == 130, f"after Stop nori exits with 130, as after Ctrl-C (got {status})")
    check(os.path.exists(stem + "_partial.exr") and os.path.exists(stem + "_partial.png"),
          "Stop wrote stopped_partial.exr and stopped_partial.png")
    wait_for(driver, lambda d: body_data(d, "state") == "exited", "the page to see nori exit")

    # The first pass against the final image: away from edges (where one jittered sample
    # per pixel differs from their average), pixels agree within the shading's change
    # across a pixel: ≤ 3 levels for 95% of the values.
    _, _, final = decode_png(open(stem + "_partial.png", "rb").read())
    differences = sorted(abs(a - b) for a, b in zip(pixels(first), pixels(final)))
    p95 = differences[int(0.95 * len(differences))]
    check(p95 <= 3, f"pass {frame} on the page matches the final PNG: 95% of values within "
          f"{p95} levels (≤ 3)")
    print(open(log).read(), end="")


def check_preview_wait(driver):
    port = free_port()
    stem = os.path.join(WORKDIR, "done")
    nori, url, log = start_nori("--preview-wait", str(port), "-D", "spp=16", "--aovs",
                                "normal", "-o", stem, SCENE_FILE, name="done")
    driver.get(url)
    wait_for(driver, lambda d: body_data(d, "state") == "done" and
             body_data(d, "drawnFrame") == body_data(d, "frame"), "the end of the render")
    _, _, shown = canvas_shot(driver)
    _, _, written = decode_png(open(stem + ".png", "rb").read())
    largest = max(abs(a - b) for a, b in zip(pixels(shown), pixels(written)))
    check(largest <= 1, f"the final image on the page equals done.png (largest difference "
          f"{largest} level)")
    Select(driver.find_element(By.ID, "layer")).select_by_value("normal")
    wait_for(driver, lambda d: d.execute_script("return shownLayer;") == "normal",
             "the normal layer")
    _, _, normals = canvas_shot(driver)
    check(pixels(normals) != pixels(shown), "picking the normal layer shows another picture")
    # The page fetched the normal layer after the render had ended; the server still
    # answers now, and nori has not exited (no sleep: the answer is the proof).
    code, body = request(url + "status")
    check(code == 200 and json.loads(body)["state"] == "done" and nori.poll() is None,
          "under --preview-wait nori keeps serving after the render")
    driver.find_element(By.ID, "stop").click()  # it reads "Close" now
    status = nori.wait(timeout=30)
    check(status == 0, f"Close ends nori with the render's status 0 (got {status})")
    print(open(log).read(), end="")


def check_resumed_render(driver):
    stem = os.path.join(WORKDIR, "resumed")
    checkpoint = stem + ".checkpoint"
    if os.path.exists(checkpoint):
        os.remove(checkpoint)
    # A render interrupted by Ctrl-C after 3 s and a checkpoint: its passes double, so the
    # checkpoint holds at least half of that time, more than the resumed run's start costs.
    args = ["--checkpoint", "0", "-D", "spp=1000000", "-o", stem, SCENE_FILE]
    log = os.path.join(WORKDIR, "interrupted.log")
    start = time.time()
    first = subprocess.Popen([NORI, "--no-progress", *args], stdout=subprocess.DEVNULL,
                             stderr=open(log, "w"))
    while (time.time() - start < 3 or not os.path.exists(checkpoint)) and first.poll() is None:
        time.sleep(0.05)
    first.send_signal(signal.SIGINT)
    check(first.wait(timeout=60) == 130, "the first run, interrupted, exits with 130")
    done = re.search(r"\((\d+) of 1000000 spp", open(log).read())
    check(done is not None and os.path.exists(checkpoint),
          f"the interrupted run kept a checkpoint of {done and done.group(1)} spp")
    interrupted_spp = int(done.group(1))

    port = free_port()
    resumed_start = time.time()
    nori, url, log = start_nori("--resume", "--preview", str(port), *args, name="resumed")
    driver.get(url)
    wait_for(driver, lambda d: int(body_data(d, "drawnFrame") or 0) >= 1, "the resumed pass")
    shown = driver.find_element(By.ID, "status").text
    since_start = time.time() - resumed_start
    progress = re.search(r"(\d+) of 1000000 spp · ([\d.]+) s elapsed", shown)
    check(progress is not None and int(progress.group(1)) > interrupted_spp,
          f"the page's first pass continues from the checkpoint's {interrupted_spp} spp "
          f"({shown!r})")
    check(float(progress.group(2)) > since_start,
          f"the page's elapsed time counts the interrupted run's ({progress.group(2)} s "
          f"shown, {since_start:.1f} s since the resumed nori started)")
    driver.find_element(By.ID, "stop").click()
    check(nori.wait(timeout=60) == 130, "Stop ends the resumed render with 130")
    check(f"at {interrupted_spp} spp" in open(log).read(),
          f"nori reports the resume at {interrupted_spp} spp")
    os.remove(checkpoint)


def check_test_file():
    port = free_port()
    test_file = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes",
                             "tests", "chi2test-diffuse.xml")
    pictures = os.path.join(WORKDIR, "pictures")
    # Pictures of an earlier run (another build's names) are not this run's.
    shutil.rmtree(pictures, ignore_errors=True)
    nori, url, log = start_nori("--preview-wait", str(port), "--pictures", pictures,
                                test_file, name="test-file")
    deadline = time.time() + 120
    while time.time() < deadline:
        status = json.loads(request(url + "status")[1])
        if status["state"] in ("passed", "failed"):
            break
        time.sleep(0.2)
    check(status["kind"] == "test" and status["state"] == "passed",
          f"a test file's preview reports it ({status['state']})")
    files = sorted(f for f in os.listdir(pictures) if f.endswith(".png"))
    check(len(status["pictures"]) == len(files) >= 1,
          f"every χ² picture is listed ({len(status['pictures'])} of {len(files)} files)")
    code, png = request(url + "picture?index=0")
    check(code == 200 and png[:8] == b"\x89PNG\r\n\x1a\n", "GET /picture?index=0 is a PNG")
    code, _ = request(url + "picture?index=%d" % len(files))
    check(code == 404, "a picture past the last is a 404")
    request(url + "stop", method="POST", headers={"X-Nori-Action": "stop"})
    check(nori.wait(timeout=30) == 0, "Close ends nori with the test's status 0")


check_busy_port()
driver = browser()
try:
    check_render_stopped_from_page(driver)
    check_preview_wait(driver)
    check_resumed_render(driver)
finally:
    driver.quit()
check_test_file()
print("all preview checks passed")
