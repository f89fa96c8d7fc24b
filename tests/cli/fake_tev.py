#!/usr/bin/env python3
"""fake_tev.py - a stand-in for the tev viewer (Tom94/tev) in the tests: it
listens on 127.0.0.1 (a free port, written to --port-file), reads tev's IPC
packets as tev's src/Ipc.cpp defines them (uint32 little-endian length, the
length included, then a type byte and the fields; strings end in NUL) and
rebuilds the image from them: CreateImage (4) makes a zeroed image of its
size and channels, UpdateImageV3 (6) writes its tile through each channel's
offset and stride. When the client closes the connection it writes the
last image to --out.exr (an uncompressed scanline EXR of FLOAT channels,
written here from the OpenEXR file layout, so that `strata diff` can compare
it) and a log of the packets to --out.log, and exits. --close-after N: close
the connection, and stop listening, after N packets (a viewer that goes
away mid-render); the log is written then.
Standard library only."""
import argparse
import socket
import struct


def read_exact(conn, n):
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


class Reader:
    def __init__(self, data):
        self.data, self.at = data, 0

    def take(self, fmt):
        v = struct.unpack_from("<" + fmt, self.data, self.at)
        self.at += struct.calcsize("<" + fmt)
        return v if len(v) > 1 else v[0]

    def string(self):
        end = self.data.index(b"\0", self.at)
        s = self.data[self.at:end].decode("utf-8")
        self.at = end + 1
        return s


def write_exr(path, width, height, channels, planes):
    """planes: {name: list of width*height floats}; NO_COMPRESSION, one line a block."""
    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
    names = sorted(channels)
    chlist = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names) + b"\0"
    box = struct.pack("<4i", 0, 0, width - 1, height - 1)
    header = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", chlist) +
              attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box) +
              attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0") +
              attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)) +
              attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line_bytes = 4 * width * len(names)
    first = len(header) + 8 * height
    offsets = b"".join(struct.pack("<Q", first + y * (8 + line_bytes)) for y in range(height))
    body = b"".join(struct.pack("<ii", y, line_bytes) + b"".join(
        struct.pack("<%df" % width, *planes[n][y * width:(y + 1) * width]) for n in names)
        for y in range(height))
    with open(path, "wb") as f:
        f.write(header + offsets + body)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--port-file", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--close-after", type=int, default=0)
    a = ap.parse_args()
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    with open(a.port_file + ".tmp", "w") as f:
        f.write("%d\n" % server.getsockname()[1])
    import os
    os.rename(a.port_file + ".tmp", a.port_file)
    conn, _ = server.accept()
    log, image, packets = [], None, 0
    while True:
        head = read_exact(conn, 4)
        if head is None:
            break
        size = struct.unpack("<I", head)[0]
        body = read_exact(conn, size - 4)
        if body is None:
            log.append("truncated packet")
            break
        r = Reader(body)
        kind = r.take("B")
        packets += 1
        if kind == 4:  # CreateImage
            focus, name = r.take("B"), r.string()
            w, h, n = r.take("iii")
            names = [r.string() for _ in range(n)]
            image = (name, w, h, names, {c: [0.0] * (w * h) for c in names})
            log.append("create %s %dx%d %s" % (name, w, h, ",".join(names)))
        elif kind == 6:  # UpdateImageV3
            focus, name = r.take("B"), r.string()
            n = r.take("i")
            names = [r.string() for _ in range(n)]
            x, y, w, h = r.take("iiii")
            offsets = [r.take("q") for _ in range(n)]
            strides = [r.take("q") for _ in range(n)]
            count = max(o + (w * h - 1) * s + 1 for o, s in zip(offsets, strides))
            data = struct.unpack_from("<%df" % count, body, r.at)
            if image is None or name != image[0]:
                log.append("update of an image never created: %s" % name)
                continue
            for c, o, s in zip(names, offsets, strides):
                plane = image[4][c]
                for j in range(h):
                    for i in range(w):
                        plane[(y + j) * image[1] + x + i] = data[o + (j * w + i) * s]
            log.append("update %s %d,%d %dx%d %s" % (name, x, y, w, h, ",".join(names)))
        else:
            log.append("packet of type %d" % kind)
        if a.close_after and packets >= a.close_after:
            log.append("closed")
            break
    conn.close()
    server.close()
    if image is not None:
        write_exr(a.out + ".exr", image[1], image[2], image[3], image[4])
    with open(a.out + ".log", "w") as f:
        f.write("\n".join(log) + "\n")


if __name__ == "__main__":
    main()
