#!/usr/bin/env python3
"""The editor's server under load (issue 20, part 10), bounded and on loopback only.

Starts `anamorph serve examples/demo.toml`, warms it up with wrk (tests/load/editor_mix.lua:
clients polling the preview and clients editing, with the misbehaving clients below) in rounds
of 10 s until its resting RSS stops climbing (under 5 % from one round to the next, at most 5 rounds: on a busy machine previews are
slower and the heap reaches its working size later), records the server's RSS and threads, then
runs wrk for SECONDS while other clients misbehave beside it:

  - slow clients trickle requests a byte at a time and never finish them (the server must
    answer 408 and close them, and nobody else may wait for them);
  - vanishing clients open long polls and frame downloads and drop them (closed, or reset
    mid-transfer);
  - malformed HTTP, oversized bodies and headers, a missing token and a foreign Host header,
    which must get 400 (or a closed connection), 413, 431, 401 and 403;
  - a canary asks for the state once a second on a fresh connection: every answer must come.

Then it checks: the server still runs; wrk saw no socket errors or timeouts and only the
statuses the API gives a well-behaved page (200, 204 for a long poll that timed out, 409 for an
edit on a stale version: concurrent editors, first writer wins); RSS at the end is within 10 % of
RSS after the warm-up; the server's threads are back to what they were. The figures go to
OUT/load.json and are printed.

Usage: editor_load.py ANAMORPH SOURCE_DIR OUT_DIR [SECONDS]  (SECONDS: default 60, or
$ANAMORPH_LOAD_SECONDS). Exit 77 (skipped) without wrk.
"""
import json
import os
import random
import re
import shutil
import socket
import struct
import subprocess
import sys
import threading
import time


def status_of(s, timeout=15.0):
    """The status of the first response on socket s, 0 when it closed without one."""
    s.settimeout(timeout)
    data = b""
    try:
        while b"\r\n" not in data:
            chunk = s.recv(4096)
            if not chunk:
                break
            data += chunk
    except (ConnectionResetError, BrokenPipeError):
        pass
    m = re.match(rb"HTTP/1\.[01] (\d{3})", data)
    return int(m.group(1)) if m else 0


class Server:
    def __init__(self, binary, scene):
        self.token = "load" + "".join(random.choice("0123456789abcdef") for _ in range(16))
        self.proc = subprocess.Popen(
            [binary, "serve", scene, "--port", "0", "--token", self.token],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = ""
        deadline = time.time() + 60
        while time.time() < deadline:
            line = self.proc.stdout.readline()
            m = re.search(r"open http://127\.0\.0\.1:(\d+)/", line)
            if m:
                self.port = int(m.group(1))
                return
            if not line and self.proc.poll() is not None:
                break
        raise RuntimeError(f"anamorph serve did not print its address: {line!r}")

    def connect(self):
        return socket.create_connection(("127.0.0.1", self.port), timeout=15)

    def request(self, method, target, body=b"", headers=None, token=True):
        head = f"{method} {target} HTTP/1.1\r\nHost: 127.0.0.1:{self.port}\r\n"
        if token:
            head += f"X-Anamorph-Token: {self.token}\r\n"
        for k, v in (headers or {}).items():
            head += f"{k}: {v}\r\n"
        head += f"Content-Length: {len(body)}\r\nConnection: close\r\n\r\n"
        return head.encode() + body

    def ask(self, method, target, body=b"", **kw):
        with self.connect() as s:
            s.sendall(self.request(method, target, body, **kw))
            return status_of(s)

    def rss_kib(self):
        with open(f"/proc/{self.proc.pid}/status") as f:
            return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))

    def threads(self):
        return len(os.listdir(f"/proc/{self.proc.pid}/task"))

    def alive(self):
        return self.proc.poll() is None

    def stop(self):
        if self.alive():
            self.proc.terminate()
            try:
                self.proc.wait(20)
            except subprocess.TimeoutExpired:
                self.proc.kill()


def run_wrk(server, lua, seconds, connections=8, threads=4):
    env = dict(os.environ, ANAMORPH_TOKEN=server.token)
    cmd = ["wrk", "-t", str(threads), "-c", str(connections), "-d", f"{seconds}s",
           "--timeout", "30s", "-s", lua, f"http://127.0.0.1:{server.port}"]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=seconds + 120)
    m = re.search(r"WRK_RESULT (\{.*\})", out.stdout)
    if out.returncode != 0 or not m:
        raise RuntimeError(f"wrk failed ({out.returncode}):\n{out.stdout}\n{out.stderr}")
    return json.loads(m.group(1))


class Misbehavers:
    """Clients that misbehave while wrk runs, each on a thread, with what they saw."""

    def __init__(self, server):
        self.server = server
        self.stop = threading.Event()
        self.seen = {}   # what -> {status: count}
        self.problems = []
        self.canary_ms = []
        self.lock = threading.Lock()
        self.threads = [threading.Thread(target=f, daemon=True) for f in
                        [self.slow] * 8 + [self.vanish, self.malformed, self.canary]]

    def note(self, what, status):
        with self.lock:
            d = self.seen.setdefault(what, {})
            d[status] = d.get(status, 0) + 1

    def problem(self, text):
        with self.lock:
            self.problems.append(text)

    def start(self):
        for t in self.threads:
            t.start()

    def join(self):
        self.stop.set()
        for t in self.threads:
            t.join(60)

    def slow(self):
        """A request trickled a byte every 0.5 s and never finished: must end with 408."""
        head = self.server.request("POST", "/api/edit", b'{"version": 1, "edits": []}')
        while not self.stop.is_set():
            s = self.server.connect()
            try:
                t0 = time.time()
                for b in head[:-4]:
                    if self.stop.is_set():
                        break
                    try:
                        s.sendall(bytes([b]))
                    except (BrokenPipeError, ConnectionResetError):
                        break
                    if self.stop.wait(0.5) or time.time() - t0 > 30:
                        break
                if self.stop.is_set():
                    break
                st = status_of(s)
                self.note("slow (trickled request)", st)
                if st != 408:
                    self.problem(f"a trickled request got {st}, not 408")
            finally:
                s.close()

    def vanish(self):
        """Long polls and frame downloads dropped: closed, or reset mid-transfer."""
        while not self.stop.is_set():
            with self.server.connect() as s:  # a long poll, then gone
                s.sendall(self.server.request("GET", "/api/frame?after=1000000000&timeout=30"))
                self.stop.wait(0.2)
            self.note("vanished long poll", "closed")
            s = self.server.connect()  # a frame download reset after 4 KiB
            s.sendall(self.server.request("GET", "/api/frame?after=0&timeout=5"))
            s.recv(4096)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            s.close()
            self.note("frame download reset mid-transfer", "reset")
            self.stop.wait(0.3)

    def malformed(self):
        """What a browser never sends, and what the guards must refuse."""
        srv = self.server
        cases = [
            ("garbage bytes", b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03" * 20, {0, 400}),
            ("bad request line", b"GET\r\n\r\n", {0, 400}),
            ("bad Content-Length", b"POST /api/edit HTTP/1.1\r\nHost: 127.0.0.1:%d\r\n"
             b"Content-Length: -5\r\n\r\n" % srv.port, {0, 400}),
            ("body over 1 MiB", srv.request("POST", "/api/edit", b"x" * (2 << 20)), {413}),
            ("headers over 16 KiB", srv.request("GET", "/api/state",
                                                headers={"X-Filler": "y" * (20 << 10)}), {431}),
            ("malformed JSON", srv.request("POST", "/api/edit", b"{\"version\": "), {400}),
            ("no token", srv.request("GET", "/api/state", token=False), {401}),
            ("foreign Host", srv.request("GET", "/api/state").replace(
                b"Host: 127.0.0.1:%d" % srv.port, b"Host: evil.example"), {403}),
        ]
        while not self.stop.is_set():
            for what, data, expected in cases:
                try:
                    with srv.connect() as s:
                        s.sendall(data)
                        st = status_of(s)
                except (BrokenPipeError, ConnectionResetError):
                    st = 0  # (refused before the whole body was sent)
                self.note(what, st)
                if st not in expected:
                    self.problem(f"{what}: got {st}, expected one of {sorted(expected)}")
            self.stop.wait(1.0)

    def canary(self):
        """A well-behaved client on a fresh connection once a second: always answered."""
        while not self.stop.is_set():
            t0 = time.time()
            try:
                st = self.server.ask("GET", "/api/state")
            except OSError as e:
                st = f"error {e}"
            ms = (time.time() - t0) * 1000
            self.note("canary GET /api/state", st)
            with self.lock:
                self.canary_ms.append(ms)
            if st != 200:
                self.problem(f"the canary got {st} after {ms:.0f} ms")
            self.stop.wait(1.0)


def settle(server):
    """RSS and threads once the editor rests: the preview of the last edit refined to its last
    pass, and the second of quiet after which the server hands its free memory back."""
    seq, deadline = 0, time.time() + 120
    while time.time() < deadline:
        with server.connect() as s:
            s.settimeout(30)
            s.sendall(server.request("GET", f"/api/frame?after={seq}&timeout=20"))
            data = b""
            while b"\r\n\r\n" not in data:
                chunk = s.recv(65536)
                if not chunk:
                    break
                data += chunk
        head = data.split(b"\r\n\r\n")[0].decode("latin-1")
        fields = dict(re.findall(r"(X-Frame-[A-Za-z]+): (\S+)", head))
        if "X-Frame-Seq" not in fields:
            break  # (204: no new frame within 20 s, so the preview is done)
        seq = int(fields["X-Frame-Seq"])
        if fields["X-Frame-Coarse"] == "0" and fields["X-Frame-Pass"] == fields["X-Frame-Passes"]:
            break
    return steady_rss(server), server.threads()


def steady_rss(server):
    """RSS once it stops moving: the heap is trimmed a second after the last change, and a busy
    machine may take longer to get there (sampled every 0.5 s, three equal readings in a row
    within 0.5 %, at most 15 s)."""
    readings = [server.rss_kib()]
    deadline = time.time() + 15
    while time.time() < deadline:
        time.sleep(0.5)
        readings.append(server.rss_kib())
        last = readings[-3:]
        if len(last) == 3 and max(last) - min(last) <= 0.005 * max(last):
            break
    return readings[-1]


def warm_up(server, lua):
    """The main run's mix (wrk and the misbehaving clients) in rounds of 10 s until the resting RSS
    grows less than 5 % in a round: the heap's working size depends on how requests interleave,
    which a busy machine changes."""
    # (The largest resting RSS of the rounds is returned: the resting size moves between working
    # sizes of the heap, 47 and 70 MB in two runs on a loaded 2-core machine, one run's warm-up
    # ending low and its end high, the other the other way round. A leak grows past all of them.)
    rounds, rss, largest = [], None, 0
    for _ in range(5):
        bad = Misbehavers(server)
        bad.start()
        rounds.append(run_wrk(server, lua, 10))
        bad.join()
        previous, (rss, threads) = rss, settle(server)
        largest = max(largest, rss)
        if previous and rss < previous * 1.05:
            break
    return rounds, largest, threads


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    binary, source, out = sys.argv[1:4]
    seconds = int(sys.argv[4] if len(sys.argv) > 4 else os.environ.get("ANAMORPH_LOAD_SECONDS", 60))
    if not shutil.which("wrk"):
        print("skipped: wrk is not installed (scripts/install-deps installs it)")
        return 77
    os.makedirs(out, exist_ok=True)
    lua = os.path.join(source, "tests", "load", "editor_mix.lua")
    server = Server(binary, os.path.join(source, "examples", "demo.toml"))
    failures = []
    try:
        rss0, threads0 = settle(server)
        warm_rounds, rss_warm, threads_warm = warm_up(server, lua)
        warm = warm_rounds[-1]
        bad = Misbehavers(server)
        bad.start()
        main_run = run_wrk(server, lua, seconds)
        bad.join()
        alive = server.alive()
        rss_end, threads_end = settle(server) if alive else (0, 0)
        growth = (rss_end - rss_warm) / rss_warm if rss_warm else 0
        rss_again = None
        if alive and growth > 0.10:
            # Past the bound: a leak keeps climbing, a heap that moved to its other working size
            # does not. One more round of the mix tells them apart.
            bad_again = Misbehavers(server)
            bad_again.start()
            run_wrk(server, lua, 10)
            bad_again.join()
            rss_again = settle(server)[0]
        report = {
            "seconds": seconds, "warmup_rounds": len(warm_rounds), "wrk_warmup": warm,
            "wrk": main_run,
            "rss_kib": {"start": rss0, "after_warmup": rss_warm, "end": rss_end,
                        "growth": round(growth, 4), "after_another_round": rss_again},
            "threads": {"start": threads0, "after_warmup": threads_warm, "end": threads_end},
            "misbehaving_clients": {k: {str(s): n for s, n in v.items()}
                                    for k, v in bad.seen.items()},
            "canary_ms": {"count": len(bad.canary_ms),
                          "median": sorted(bad.canary_ms)[len(bad.canary_ms) // 2]
                          if bad.canary_ms else None,
                          "max": max(bad.canary_ms) if bad.canary_ms else None},
        }
        with open(os.path.join(out, "load.json"), "w") as f:
            json.dump(report, f, indent=2)
        print(json.dumps(report, indent=2))

        if not alive:
            failures.append(f"the server died (exit {server.proc.returncode}): "
                            f"{server.proc.stderr.read()[-2000:]}")
        runs = [(r, f"warm-up round {i + 1}") for i, r in enumerate(warm_rounds)]
        for run, name in runs + [(main_run, "main run")]:
            errs = {k: v for k, v in run["errors"].items() if k != "status" and v}
            if errs:
                failures.append(f"wrk's {name} saw socket errors or timeouts: {errs}")
            unexpected = {k: v for k, v in run["statuses"].items() if k not in ("200", "204", "409")}
            if unexpected:
                failures.append(f"wrk's {name} got unexpected statuses: {unexpected}")
            if run["statuses"].get("200", 0) == 0:
                failures.append(f"wrk's {name} got no 200 at all: {run['statuses']}")
        # Growth is what a leak shows; a drop only means the warm-up's reading came before the
        # server handed idle pages back (seen at -32 % on a loaded 2-core machine), so it is
        # reported above but is not a failure.
        if growth > 0.10 and (rss_again is None or rss_again > rss_end * 1.05):
            failures.append(f"RSS grew {growth:+.1%} between the warm-up ({rss_warm} KiB) and "
                            f"the end ({rss_end} KiB), the bound is 10 %, and went on growing "
                            f"in another round ({rss_again} KiB)")
        if threads_end > threads_warm + 2:
            failures.append(f"{threads_end} threads at the end against {threads_warm} after the "
                            "warm-up: connections were not let go")
        failures += bad.problems[:20]
        for what in ("slow (trickled request)", "canary GET /api/state", "body over 1 MiB"):
            if not bad.seen.get(what):
                failures.append(f"no '{what}' completed during the run")
        if alive and server.ask("GET", "/api/state") != 200:
            failures.append("the server does not answer after the run")
    finally:
        server.stop()
    for f in failures:
        print("FAILED:", f)
    print("load test:", "failed" if failures else "passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
