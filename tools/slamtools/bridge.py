# SPDX-License-Identifier: MIT
"""The robot's link over a WebSocket, for the browser page (tools/web/): `telemetry.py
serve` runs it. The robot's bytes go to every page connected, untouched, as binary
messages; a page's binary messages (command frames) go to the robot. The same server hands
out the page itself, so a robot's computer (a Raspberry Pi) serves its own viewer: open
http://ROBOT:PORT/ in any browser on the network.

A page that connects mid-run first gets the latest HELLO, every map row and the last
STATUS the robot sent, re-framed as the robot framed them, so it draws the whole map at
once instead of after the robot's next pass over it (about 30 s). A source that goes away
(a USB serial cable pulled, the simulator ended) is tried again every second."""
import asyncio
import errno
import http
import mimetypes
import os
import socket
import stat
import sys
import termios
import tty

from . import link as slamlink
from .errors import ToolError

WEB_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "web")
LINK_PATH = "/link"
FILE_CHUNK = 65536
BACKLOG = 1 << 22  # bytes a slow page may fall behind by before the bridge drops some
BAUDS = {9600: termios.B9600, 19200: termios.B19200, 38400: termios.B38400,
         57600: termios.B57600, 115200: termios.B115200, 230400: termios.B230400,
         460800: termios.B460800, 921600: termios.B921600}


def need_websockets():
    try:
        import websockets.legacy.server  # noqa: F401
    except ImportError:
        raise ToolError("the bridge needs python3-websockets (tools/install-deps.sh web)")


class Catchup:
    """What a page joining late needs to draw the robot's state at once: the latest HELLO,
    every map row since it, and the last STATUS, as frames."""

    def __init__(self):
        self.dec = slamlink.Decoder()
        self.hello = None
        self.geometry = None
        self.rows = {}
        self.status = None

    def feed(self, data):
        for ftype, payload in self.dec.feed(data):
            fr = slamlink.decode(ftype, payload)
            if fr is None:
                continue
            raw = slamlink.frame(ftype, payload)
            if fr["type"] == "hello":
                if (fr["a"], fr["b"]) != self.geometry:
                    self.rows.clear()
                self.geometry = (fr["a"], fr["b"])
                self.hello = raw
            elif fr["type"] == "map_row" and self.hello is not None:
                self.rows[(fr["map"], fr["row"], fr["first"])] = raw
            elif fr["type"] == "status":
                self.status = raw

    def frames(self):
        """The frames, then the start of the frame under way: the live bytes that follow
        continue it, so the page's stream has no seam."""
        head = [self.hello] + [self.rows[k] for k in sorted(self.rows)] if self.hello else []
        return b"".join(head + ([self.status] if self.status else []) + [bytes(self.dec.buf)])


class Client:
    """A page: what is sent to it goes through its own queue, in order; a page that falls
    more than BACKLOG behind loses bytes, as a UART nobody reads does."""

    def __init__(self, ws):
        self.ws = ws
        self.queue = asyncio.Queue()
        self.queued = 0
        self.dropped = 0
        self.task = asyncio.ensure_future(self.pump())

    def put(self, data):
        if self.queued > BACKLOG:
            self.dropped += len(data)
            return
        self.queued += len(data)
        self.queue.put_nowait(data)

    async def pump(self):
        try:
            while True:
                data = await self.queue.get()
                self.queued -= len(data)
                await self.ws.send(data)
        except Exception:  # the page went away; its handler ends
            pass


class Bridge:
    """One source (a serial device, a pseudo-terminal, or a file) and the pages watching."""

    def __init__(self, source, baud=115200, follow=False, quiet=False, record=None):
        self.source = source
        self.record = None
        self.baud = baud
        self.follow = follow
        self.quiet = quiet
        self.clients = set()
        self.fd = None
        self.catchup = Catchup()
        try:
            mode = os.stat(source).st_mode
        except OSError as e:
            raise ToolError("%s: %s" % (source, e.strerror))
        if stat.S_ISDIR(mode):
            raise ToolError("%s is a directory: give a serial device, a pseudo-terminal or a "
                              "telemetry file" % source)
        if baud not in BAUDS:
            raise ToolError("--baud %d: not one of %s" % (baud, ", ".join(map(str, BAUDS))))
        self.device = stat.S_ISCHR(mode)
        if record is not None and not self.device:
            raise ToolError("--record: the source is a file already")
        if self.device:
            self.open_device()  # fail now, with the reason, rather than in the loop
        if record is not None:
            try:
                self.record = open(record, "ab")
            except OSError as e:
                raise ToolError("--record %s: %s" % (record, e.strerror))

    def say(self, text):
        if not self.quiet:
            print("telemetry serve: %s" % text, file=sys.stderr, flush=True)

    def describe(self):
        if not self.device:
            return ("serving the recording %s%s: it takes no commands" %
                    (self.source, ", followed as it grows" if self.follow else ""))
        return "serving the robot on %s%s: commands go to it" % (
            self.source, " at %d baud" % self.baud if not self.pty else "")

    # ---- a device: one reader, every page ----------------------------------------------------

    def open_device(self):
        try:
            fd = os.open(self.source, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError as e:
            raise ToolError("cannot open %s: %s" % (self.source, e.strerror))
        self.pty = os.path.realpath(self.source).startswith("/dev/pts/")
        if os.isatty(fd):
            try:
                tty.setraw(fd)
                if not self.pty:
                    attrs = termios.tcgetattr(fd)
                    attrs[4] = attrs[5] = BAUDS[self.baud]
                    attrs[2] |= termios.CLOCAL | termios.CREAD
                    termios.tcsetattr(fd, termios.TCSANOW, attrs)
            except termios.error as e:
                os.close(fd)
                raise ToolError("cannot set up %s: %s" % (self.source, e))
        self.fd = fd

    def close_device(self, why):
        loop = asyncio.get_running_loop()
        loop.remove_reader(self.fd)
        os.close(self.fd)
        self.fd = None
        self.say("%s: %s; trying it again every second" % (self.source, why))
        self.broadcast_text("the robot's link %s closed (%s); waiting for it to come back"
                            % (self.source, why))
        loop.call_later(1.0, self.reopen)

    def reopen(self):
        try:
            self.open_device()
        except ToolError:
            asyncio.get_running_loop().call_later(1.0, self.reopen)
            return
        self.say("%s is back" % self.source)
        self.broadcast_text(self.describe())
        asyncio.get_running_loop().add_reader(self.fd, self.readable)

    def readable(self):
        try:
            data = os.read(self.fd, 65536)
        except BlockingIOError:
            return
        except OSError as e:
            # EIO: the pseudo-terminal's other end closed (the program ended).
            self.close_device(e.strerror if e.errno != errno.EIO else "the other end closed")
            return
        if not data:
            self.close_device("end of file")
            return
        self.catchup.feed(data)
        if self.record is not None:
            # A terminal gives each byte to one reader: recording here is how the same
            # bytes reach both the pages and a file (telemetry.py to-bag, to-readings).
            self.record.write(data)
            self.record.flush()
        for c in list(self.clients):
            c.put(data)

    def broadcast_text(self, text):
        for c in list(self.clients):
            c.put(text)

    def command(self, data):
        """A page's bytes to the robot; a text telling why when they cannot go."""
        if not self.device:
            return "a recording takes no commands"
        if self.fd is None:
            return "the robot's link is closed; the command was not sent"
        try:
            n = os.write(self.fd, data)
        except OSError as e:
            return "the command could not be written: %s" % e.strerror
        if n != len(data):
            return "the link took %d of the command's %d bytes" % (n, len(data))
        return None

    # ---- the pages -----------------------------------------------------------------------

    async def handler(self, ws, path=None):
        path = path if path is not None else ws.path
        if not path.startswith(LINK_PATH):
            await ws.close(1008, "the robot's link is at %s" % LINK_PATH)
            return
        peer = "%s:%s" % ws.remote_address[:2] if ws.remote_address else "a page"
        self.say("%s connected" % peer)
        client = Client(ws)
        client.put(self.describe())
        feeder = None
        if self.device:
            client.put(self.catchup.frames())
            self.clients.add(client)
        else:
            feeder = asyncio.ensure_future(self.feed_file(client))
        try:
            async for msg in ws:
                if isinstance(msg, str):
                    continue
                why = self.command(msg)
                if why is not None:
                    client.put(why)
        except Exception:
            pass
        finally:
            self.clients.discard(client)
            client.task.cancel()
            if feeder is not None:
                feeder.cancel()
            self.say("%s left%s" % (peer, "; %d bytes it fell behind by were dropped"
                                    % client.dropped if client.dropped else ""))

    async def feed_file(self, client):
        """A recording from its start, then what is added to it while --follow; read only
        as fast as the page takes it."""
        try:
            with open(self.source, "rb") as f:
                while True:
                    if client.queued > FILE_CHUNK * 4:
                        await asyncio.sleep(0.05)
                        continue
                    data = f.read(FILE_CHUNK)
                    if data:
                        client.put(data)
                    elif self.follow:
                        await asyncio.sleep(0.2)
                    else:
                        client.put("the end of %s" % self.source)
                        return
        except OSError as e:
            client.put("reading %s: %s" % (self.source, e.strerror))

    async def http(self, path, headers):
        """The page's files for plain HTTP requests; None lets a WebSocket through."""
        if "upgrade" in headers.get("Connection", "").lower():
            return None
        name = path.split("?", 1)[0]
        if name == "/":
            return (http.HTTPStatus.FOUND, [("Location", "/index.html?connect")], b"")
        name = name.lstrip("/")
        files = sorted(os.listdir(WEB_DIR))
        if name not in files or not name.endswith((".html", ".js", ".css", ".png")):
            return (http.HTTPStatus.NOT_FOUND, [("Content-Type", "text/plain")],
                    b"not found: the page is at /\n")
        with open(os.path.join(WEB_DIR, name), "rb") as f:
            body = f.read()
        kind = mimetypes.guess_type(name)[0] or "application/octet-stream"
        if kind.startswith("text/") or kind.endswith("javascript"):
            kind += "; charset=utf-8"
        return (http.HTTPStatus.OK, [("Content-Type", kind), ("Cache-Control", "no-cache")], body)


def addresses(host, port):
    """Where a browser finds the page."""
    if host in ("0.0.0.0", "::", ""):
        names = {socket.gethostname()}
        try:
            for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET):
                names.add(info[4][0])
        except OSError:
            pass
        names.discard("127.0.1.1")
        return ["http://%s:%d/" % (n, port) for n in sorted(names)]
    return ["http://%s:%d/" % (host if ":" not in host else "[%s]" % host, port)]


async def run(bridge, host, port, ready=None):
    import websockets.legacy.server as wss
    try:
        server = await wss.serve(bridge.handler, host, port, process_request=bridge.http,
                                 max_size=2 ** 16, compression=None)
    except OSError as e:
        raise ToolError("cannot listen on %s port %d: %s" % (host, port, e.strerror))
    if bridge.device:
        asyncio.get_running_loop().add_reader(bridge.fd, bridge.readable)
    bound = server.sockets[0].getsockname()[1]
    bridge.say(bridge.describe())
    print("telemetry serve: the page: %s (its WebSocket: ws://%s:%d%s); Ctrl-C ends"
          % (" or ".join(addresses(host, bound)), host, bound, LINK_PATH), flush=True)
    if ready is not None:
        ready(bound)
    await asyncio.Future()  # until Ctrl-C or SIGTERM


def serve(source, host="127.0.0.1", port=8765, baud=115200, follow=False, quiet=False,
          record=None):
    """Run the bridge until interrupted; ToolError for what the user must fix."""
    need_websockets()
    bridge = Bridge(source, baud, follow, quiet, record)
    try:
        asyncio.run(run(bridge, host, port))
    finally:
        if bridge.record is not None:
            bridge.record.close()
