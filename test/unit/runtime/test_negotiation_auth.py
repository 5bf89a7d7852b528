"""Authenticated negotiation messages (docs/negotiation.md, "Only real peers negotiate"): a secret read
from a file only its owner may read, an HMAC over the whole message, its receiver and the request a
reply answers, a nonce against replays."""
from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.resilience.negotiation import Message, classes_authenticator, classes_from_data
from ltl_stack.runtime.resilience.negotiation.auth import Authenticator, SecretError, read_secret

SECRET = b"0123456789abcdef0123456789abcdef"


class Clock:
    def __init__(self) -> None:
        self.now = 1_000_000.0

    def __call__(self) -> float:
        return self.now


def parties(clock=None):
    clock = clock or Clock()
    return (Authenticator("P", {"Q": SECRET}, clock=clock), Authenticator("Q", {"P": SECRET}, clock=clock), clock)


OFFER = Message("offer", "P", "P->Q", 0, "[SYS_TRANS]\nx'\n", ("always next x",))


def test_a_signed_message_passes_once_and_a_replay_is_refused():
    p, q, _ = parties()
    signed = p.sign(OFFER, "Q")
    assert signed.mac and signed.nonce and q.check(signed) is None
    assert q.check(signed) == "replayed message for P"


def test_unsigned_wrongly_signed_and_foreign_messages_are_refused_in_one_line():
    p, q, clock = parties()
    assert q.check(OFFER) == "unsigned message for P"
    wrong = Authenticator("P", {"Q": b"another secret of 32 bytes......"}, clock=clock).sign(OFFER, "Q")
    assert q.check(wrong) == "wrongly signed message for P"
    assert q.check(dataclasses.replace(p.sign(OFFER, "Q"), sender="Z")) == "no secret shared with 'Z'"
    # a message signed for Q is not valid at R, though R shares the fleet's secret
    r = Authenticator("R", {"P": SECRET}, clock=clock)
    assert r.check(p.sign(OFFER, "Q")) == "wrongly signed message for P"


@given(field=st.sampled_from(["kind", "session", "round", "text", "english", "realizable", "reason", "nonce"]),
       text=st.text(max_size=20))
def test_changing_any_field_breaks_the_signature(field, text):
    p, q, _ = parties()
    signed = p.sign(dataclasses.replace(OFFER, reason=text), "Q")
    value = getattr(signed, field)
    if field == "round":
        changed = value + 1
    elif field == "realizable":
        changed = not value
    elif field == "english":
        changed = (*value, text)
    else:
        changed = f"{value}{text or 'x'}"
    refusal = q.check(dataclasses.replace(signed, **{field: changed}))
    assert refusal == "wrongly signed message for P", refusal


def test_a_reply_is_bound_to_the_request_it_answers_and_old_messages_are_stale():
    p, q, clock = parties()
    request = p.sign(OFFER, "Q")
    reply = q.sign(Message("offer", "Q", "P->Q"), "P", reply_to=request.nonce)
    other = p.sign(OFFER, "Q")
    assert p.check(reply, reply_to=other.nonce, sender="Q") == "wrongly signed message for Q"
    assert p.check(reply, reply_to=request.nonce, sender="Q") is None
    old = p.sign(OFFER, "Q")
    clock.now += 301
    assert q.check(old).startswith("stale message for P (301 s old")


def test_a_secret_readable_by_others_is_refused(tmp_path):
    path = tmp_path / "fleet.key"
    path.write_bytes(SECRET + b"\n")
    path.chmod(0o644)
    with pytest.raises(SecretError, match=r"fleet.key: the negotiation secret is accessible to group or others "
                                          r"\(mode 0644\); run: chmod 600"):
        read_secret(path)
    path.chmod(0o600)
    assert read_secret(path) == SECRET
    short = tmp_path / "short.key"
    short.write_bytes(b"abc")
    short.chmod(0o600)
    with pytest.raises(SecretError, match="shorter than 16 bytes"):
        read_secret(short)
    with pytest.raises(SecretError, match="missing.key: cannot read"):
        read_secret(tmp_path / "missing.key")


def test_the_mapping_names_the_fleet_secret_or_one_per_pair(tmp_path):
    (tmp_path / "fleet.key").write_bytes(SECRET)
    (tmp_path / "fleet.key").chmod(0o600)
    (tmp_path / "pq.key").write_bytes(SECRET[::-1])
    (tmp_path / "pq.key").chmod(0o600)
    data = {"robot": "P", "secret_file": "fleet.key", "peers": {"Q": {"secret_file": "pq.key"}, "R": {}}}
    auth = classes_authenticator(classes_from_data(data, str(tmp_path / "P.yaml"), 1))
    assert auth.secrets == {"Q": SECRET[::-1], "R": SECRET}
    assert classes_authenticator(classes_from_data({"robot": "P", "peers": {"Q": {}}})) is None
