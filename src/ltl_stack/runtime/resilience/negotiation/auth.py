"""Authenticated negotiation messages: a shared secret, an HMAC over each whole message, a nonce.

ROS 1 does not authenticate anything: a caller id is what the caller says it is, and anyone who can
reach a robot's TCP port can call its ``~negotiate``. A fleet (or a pair of robots) that shares a
secret signs every message of Alg. 4:

* the **secret** is read from a file the robot names (``negotiation: secret_file:`` in its mapping,
  or ``peers: <name>: secret_file:`` for one pair); a file that group or others may read or write is
  refused (``read_secret``), so is one shorter than ``MIN_SECRET_BYTES``;
* the **MAC** is HMAC-SHA256 (``hmac``, ``hashlib``) over every field of the message — kind, sender,
  session, round, spec text, its English, realizable, reason, nonce — and over the receiving robot's
  name (a message to Q cannot be replayed to R) and, for a reply, over the nonce of the request it
  answers (a recorded reply cannot answer another request);
* the **nonce** is the sender's wall-clock time in milliseconds and 64 random bits: a message older
  or newer than ``window`` seconds (the robots' clocks must agree within it), or whose nonce was
  already seen within the window, is a replay and refused.

``Authenticator.check`` gives the one-line reason a message is refused, or None; a refused message
is answered before anything else looks at it, so it uses nothing up (no negotiation starts, the
pair's negotiation is not spent). This keeps out whoever does not hold the secret; it does not
protect the topics the robots read (ROS 1 topics are unauthenticated: docs/negotiation.md).
"""
from __future__ import annotations

import hashlib
import hmac
import json
import os
import secrets
import stat
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path

from ltl_stack.errors import UserError

#: a shorter secret is refused (16 bytes of a random key; a hex or base64 text is longer)
MIN_SECRET_BYTES = 16
#: how far a nonce's time may be from the receiver's clock (seconds)
DEFAULT_WINDOW = 300.0


class SecretError(UserError):
    """A secret file that cannot be used (one line naming the file, exit code 2)."""


def read_secret(path: str | Path) -> bytes:
    """The secret in ``path`` (surrounding white space stripped); ``SecretError`` when the file is
    missing, readable or writable by group or others, or too short."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
        data = path.read_bytes().strip()
    except OSError as err:
        raise SecretError(f"{path}: cannot read the negotiation secret: {err.strerror or err}") from None
    if not stat.S_ISREG(mode):
        raise SecretError(f"{path}: the negotiation secret must be a file")
    if mode & 0o077:
        raise SecretError(f"{path}: the negotiation secret is accessible to group or others (mode "
                          f"{stat.S_IMODE(mode):04o}); run: chmod 600 {path}")
    if len(data) < MIN_SECRET_BYTES:
        raise SecretError(f"{path}: the negotiation secret is shorter than {MIN_SECRET_BYTES} bytes")
    return data


def new_nonce(clock: Callable[[], float] = time.time) -> str:
    """``<milliseconds>-<16 hex digits>``: when, and something nobody can guess."""
    return f"{int(clock() * 1000)}-{secrets.token_hex(8)}"


def mac(secret: bytes, fields: Mapping[str, object], receiver: str, reply_to: str = "") -> str:
    """HMAC-SHA256 (hex) of the message ``fields`` (every one but ``mac``), the receiving robot and
    the request a reply answers, in one canonical JSON text."""
    body = {k: v for k, v in fields.items() if k != "mac"}
    payload = json.dumps({"message": body, "to": receiver, "reply_to": reply_to}, sort_keys=True,
                         separators=(",", ":"), ensure_ascii=True)
    return hmac.new(secret, payload.encode("ascii"), hashlib.sha256).hexdigest()


class Authenticator:
    """Signs what this robot sends and checks what it receives (see the module docstring).
    ``secrets`` maps each peer to the secret shared with it."""

    def __init__(self, robot: str, secrets_by_peer: Mapping[str, bytes], *, window: float = DEFAULT_WINDOW,
                 clock: Callable[[], float] = time.time) -> None:
        self.robot = robot
        self.secrets = dict(secrets_by_peer)
        self.window = window
        self.clock = clock
        self._seen: dict[str, float] = {}  # nonce -> its time, for the window
        self._lock = threading.Lock()

    def sign(self, message, receiver: str, reply_to: str = ""):
        """``message`` (a ``Message``) with a fresh nonce and its MAC for ``receiver``."""
        message = replace(message, nonce=new_nonce(self.clock), mac="")
        return replace(message, mac=mac(self.secrets[receiver], message.to_dict(), receiver, reply_to))

    def check(self, message, reply_to: str = "", sender: str | None = None) -> str | None:
        """Why ``message`` is refused (one line), or None when it is authentic and fresh. ``sender``:
        the peer it must come from (a reply), else any peer with a secret."""
        who = sender if sender is not None else message.sender
        if who != message.sender:
            return f"a reply from {message.sender[:40]!r}, expected {who}"
        secret = self.secrets.get(who)
        if secret is None:
            return f"no secret shared with {who[:40]!r}"
        if not message.mac:
            return f"unsigned message for {who}"
        expected = mac(secret, message.to_dict(), self.robot, reply_to)
        if not hmac.compare_digest(expected, str(message.mac)):
            return f"wrongly signed message for {who}"
        try:
            stamp = int(str(message.nonce).split("-", 1)[0]) / 1000.0
        except ValueError:
            return f"message for {who} without a valid nonce"
        now = self.clock()
        if abs(now - stamp) > self.window:
            return f"stale message for {who} ({now - stamp:.0f} s old; clocks must agree within {self.window:g} s)"
        with self._lock:
            for nonce, seen in list(self._seen.items()):
                if now - seen > 2 * self.window:
                    del self._seen[nonce]
            if message.nonce in self._seen:
                return f"replayed message for {who}"
            self._seen[message.nonce] = now
        return None


def load_authenticator(robot: str, fleet_file: str | None, pair_files: Mapping[str, str | None],
                       base: str | Path = ".") -> Authenticator | None:
    """The authenticator of a robot whose declaration names ``fleet_file`` (shared by every peer) and
    per-peer ``pair_files`` (each overrides the fleet's for its peer); relative paths are read from
    ``base`` (the mapping's folder). None when no file is named: negotiation is unauthenticated."""
    files = {peer: path or fleet_file for peer, path in pair_files.items()}
    if not any(files.values()):
        return None
    loaded: dict[str, bytes] = {}
    by_peer = {}
    for peer, path in files.items():
        if not path:
            raise SecretError(f"negotiation: no secret for peer {peer} while others have one "
                              "(secret_file: for the fleet, or for each peer)")
        full = str(Path(base) / os.path.expanduser(path))
        if full not in loaded:
            loaded[full] = read_secret(full)
        by_peer[peer] = loaded[full]
    return Authenticator(robot, by_peer)
