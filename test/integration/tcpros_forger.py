"""A raw TCPROS service client that says it is any node it likes: it asks the master where a service
is, opens a TCP connection to it and writes a connection header whose ``callerid`` is whatever it is
given — no node, no registration, nothing at the master. What an outsider on the LAN can do
(docs/negotiation.md, threat model)."""
from __future__ import annotations

import io
import socket
import struct
import xmlrpc.client

from ltl_stack.srv import Negotiate, NegotiateResponse


def _fields(data: dict[str, str]) -> bytes:
    body = b"".join(struct.pack("<I", len(f"{k}={v}".encode())) + f"{k}={v}".encode() for k, v in data.items())
    return struct.pack("<I", len(body)) + body


def _read(sock: socket.socket, size: int) -> bytes:
    chunks = b""
    while len(chunks) < size:
        chunk = sock.recv(size - len(chunks))
        if not chunk:
            raise ConnectionError("the service closed the connection")
        chunks += chunk
    return chunks


def forge(master_uri: str, service: str, request, callerid: str, timeout: float = 60.0) -> NegotiateResponse:
    """Call ``service`` with ``request`` (a ``NegotiateRequest``) as ``callerid``; its response."""
    code, message, uri = xmlrpc.client.ServerProxy(master_uri).lookupService("/forger", service)
    if code != 1:
        raise ConnectionError(f"{service}: {message}")
    host, port = uri[len("rosrpc://"):].rsplit(":", 1)
    with socket.create_connection((host, int(port)), timeout=timeout) as sock:
        sock.sendall(_fields({"callerid": callerid, "service": service, "md5sum": Negotiate._md5sum,
                              "persistent": "0"}))
        (size,) = struct.unpack("<I", _read(sock, 4))
        header = _read(sock, size)
        if b"error=" in header:
            raise ConnectionError(header.decode(errors="replace"))
        buffer = io.BytesIO()
        request.serialize(buffer)
        sock.sendall(struct.pack("<I", len(buffer.getvalue())) + buffer.getvalue())
        ok = _read(sock, 1)
        (size,) = struct.unpack("<I", _read(sock, 4))
        payload = _read(sock, size)
    if ok != b"\x01":
        raise ConnectionError(payload.decode(errors="replace"))
    return NegotiateResponse().deserialize(payload)
