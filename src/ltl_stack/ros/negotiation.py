"""Integrative negotiation over ROS (thesis §4.8, Alg. 4; docs/negotiation.md).

Each executor that negotiates offers the service ``~negotiate`` (``ltl_stack/Negotiate``): the
request is one message of the initiator, the response the responder's own message of the same
exchange (offer, status 1, status 2, or an abort). The protocol logic is ROS-free
(``ltl_stack.runtime.resilience.negotiation``); this module is the transport and the reporting:

* ``NegotiationEndpoint(negotiator, strategy, controller)``: serves ``~negotiate`` (under the
  controller's lock, ``Negotiator.serve``), gives the negotiator its transport (a service call per
  message, bounded by ``timeout``: a peer whose service does not appear or does not answer in time is
  a fault, the negotiation fails and nothing is adopted), expires a negotiation whose initiator went
  silent, and publishes ``~negotiations`` (``std_msgs/String``, latched: a JSON list of the reports —
  with whom, what was sent and received in words, outcome) and a ``negotiation`` status
  on ``/diagnostics``;
* a peer's service is the ``service:`` of its mapping entry, else
  ``<parent namespace>/<peer>/controller_executor/negotiate`` (the executors of a scenario side by side,
  e.g. ``/kitchen/D/…`` and ``/kitchen/A/…``);
* with an ``Authenticator`` (the mapping's ``secret_file``, ``runtime.resilience.negotiation.auth``) every message
  sent is signed and every message received is checked first: an unsigned, wrongly signed or replayed
  request is refused in one WARN line before anything else reads it, a reply that fails the check is
  a fault of the negotiation. Without one, one WARN line at start-up says negotiation is
  unauthenticated;
* ``RegistrationWatch``: every ``period`` seconds the endpoint asks the master who serves its
  ``~negotiate`` (an XML-RPC call bounded by a timeout, in a timer thread, never under the
  controller's lock); when another URI answers (someone called ``registerService`` over it) it
  reports ERROR on ``/diagnostics`` and registers its own service again.
"""
from __future__ import annotations

import json
import os
import threading
import time
import xmlrpc.client
from collections.abc import Callable
from typing import Any

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from std_msgs.msg import String

from ltl_stack.ros.master import timed_proxy
from ltl_stack.runtime.resilience.characterize import ResilientStrategy
from ltl_stack.runtime.resilience.negotiation import (
    Classes,
    Message,
    Negotiation,
    Negotiator,
    Outcome,
    Peer,
    caller_refusal,
)
from ltl_stack.runtime.resilience.negotiation.auth import Authenticator
from ltl_stack.srv import Negotiate, NegotiateRequest, NegotiateResponse

FIELDS = ("kind", "sender", "session", "round", "text", "english", "realizable", "reason", "nonce", "mac")
#: Default bound of one exchange (seconds); ~negotiation_timeout.
DEFAULT_TIMEOUT = 5.0
#: refused messages logged one by one before the log thins out to one in 1000
LOGGED_REFUSALS = 10
#: clauses sent/received logged per negotiation (the full lists are in ~negotiations)
LOGGED_CLAUSES = 20
#: how often the endpoint checks its ~negotiate registration at the master (seconds)
REGISTRATION_PERIOD = 2.0


def to_ros(message: Message, kind: type = NegotiateRequest) -> Any:
    data = message.to_dict()
    return kind(**{f: data[f] for f in FIELDS})


def from_ros(msg: Any) -> Message:
    return Message.from_dict({f: getattr(msg, f) for f in FIELDS})


def default_service(peer: str, namespace: str | None = None) -> str:
    """``<parent of our namespace>/<peer>/controller_executor/negotiate``."""
    namespace = namespace if namespace is not None else rospy.get_namespace()
    parent = rosgraph.names.namespace(namespace.rstrip("/") or "/")
    return rosgraph.names.ns_join(parent, f"{peer}/controller_executor/negotiate")


def service_of(peer: Peer) -> str:
    """The peer's ``~negotiate`` service: its ``service:`` (resolved), else ``default_service``."""
    return rospy.resolve_name(peer.service) if peer.service else default_service(peer.name)


def node_of(service: str) -> str:
    """The node that serves ``service`` (``~negotiate`` is private: its namespace is the node)."""
    return rosgraph.names.namespace(service).rstrip("/") or "/"


#: a test hook (never set in use): messages the transport drops, once each, to test the commit protocol
#: on real nodes: comma-separated ``request|reply:KIND[:ROUND]`` (``reply:commit``: the confirmation of
#: the decision is lost; ``reply:status:2``: the responder's status 2)
TEST_DROP_VARIABLE = "LTL_STACK_TEST_DROP"


def _test_drops() -> list[str]:
    return [x.strip() for x in os.environ.get(TEST_DROP_VARIABLE, "").split(",") if x.strip()]


def _dropped(drops: list[str], way: str, message: Message) -> bool:
    for key in (f"{way}:{message.kind}:{message.round}", f"{way}:{message.kind}"):
        if key in drops:
            drops.remove(key)
            return True
    return False


def service_transport(timeout: float = DEFAULT_TIMEOUT, auth: Authenticator | None = None,
                      ) -> Callable[[Peer], Callable[[Message], Message]]:
    """The initiator's transport: one ``Negotiate`` service call per message, bounded by ``timeout``
    (a service that does not appear, or a call that does not return, in time is a ``TimeoutError``;
    any other failure a ``ConnectionError``: both are faults of the negotiation). With ``auth`` each
    message is signed and a reply that is not signed by the peer for it is a ``ConnectionError``."""
    drops = _test_drops()

    def transport(peer: Peer) -> Callable[[Message], Message]:
        name = service_of(peer)

        def call(message: Message) -> Message:
            if auth is not None:
                message = auth.sign(message, peer.name)
            if _dropped(drops, "request", message):
                raise TimeoutError(f"{name}: request dropped ({TEST_DROP_VARIABLE})")
            result: dict[str, Any] = {}

            def work() -> None:
                try:
                    rospy.wait_for_service(name, timeout=timeout)
                    result["reply"] = rospy.ServiceProxy(name, Negotiate)(to_ros(message))
                except Exception as err:  # noqa: BLE001 - every transport failure is a fault of the negotiation
                    result["error"] = err

            worker = threading.Thread(target=work, name=f"negotiate_{peer.name}", daemon=True)
            worker.start()
            worker.join(timeout)
            if worker.is_alive():
                raise TimeoutError(f"{name}: no answer within {timeout:g} s")
            if "error" in result:
                error = result["error"]
                if isinstance(error, rospy.ROSException) and "timeout" in str(error).lower():
                    raise TimeoutError(f"{name}: service not available within {timeout:g} s")
                raise ConnectionError(f"{name}: {error}")
            reply = from_ros(result["reply"])
            if _dropped(drops, "reply", message):
                raise TimeoutError(f"{name}: reply dropped ({TEST_DROP_VARIABLE})")
            if auth is not None:
                refusal = auth.check(reply, reply_to=message.nonce, sender=peer.name)
                if refusal is not None:
                    raise ConnectionError(f"{name}: reply refused: {refusal}"
                                          + (f" ({reply.reason[:200]})" if reply.kind == "abort" else ""))
            return reply

        return call

    return transport


class NegotiationEndpoint:
    """The ROS side of one robot's negotiations (see the module docstring). Create after ``init_node``."""

    def __init__(self, negotiator: Negotiator, strategy: Any, controller: Any, *, timeout: float = DEFAULT_TIMEOUT,
                 service_name: str = "~negotiate", on_report: Callable[[Negotiation], None] | None = None,
                 auth: Authenticator | None = None, registration_period: float = REGISTRATION_PERIOD) -> None:
        self.negotiator = negotiator
        self.strategy = strategy
        self.controller = controller
        self.timeout = timeout
        self.on_report = on_report
        self.auth = auth
        self.name = rospy.get_name()
        self.pub = rospy.Publisher("~negotiations", String, queue_size=10, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        if negotiator.transport is None:
            negotiator.transport = service_transport(timeout, auth)
        if auth is None:
            rospy.logwarn("%s: negotiation is unauthenticated (no secret_file in the mapping's negotiation: key): "
                          "anyone who reaches this robot's ~negotiate can negotiate as a peer (docs/negotiation.md)",
                          self.name)
        #: the latest hijack of ~negotiate the watch repaired (for the diagnostics), or ""
        self.hijack = ""
        #: the node that serves each declared peer's negotiation: the only one that may speak for it
        self.peer_nodes = {name: node_of(service_of(peer)) for name, peer in negotiator.classes.peers.items()}
        self.refusals = 0
        self.service = rospy.Service(service_name, Negotiate, self._on_request)
        self.expiry = rospy.Timer(rospy.Duration(max(timeout / 2.0, 0.1)), self._expire)
        #: the commit protocol after a lost message: ask again (``Negotiator.settle``), in a timer thread
        self.settling = rospy.Timer(rospy.Duration(max(timeout / 2.0, 0.5)),
                                    lambda _event: negotiator.settle(strategy, controller))
        self.watch = RegistrationWatch(self.service, on_hijack=self._hijacked, timeout=min(timeout, 2.0))
        self.watch_timer = rospy.Timer(rospy.Duration(registration_period), lambda _event: self.watch.check())
        # last: a negotiation may start on another thread at once, and its reports use all of the above
        negotiator.on_change = self._changed
        self._publish()

    def service_of(self, peer: Peer) -> str:
        return service_of(peer)

    # --- responder -------------------------------------------------------------------------------------------
    def _on_request(self, request: Any) -> NegotiateResponse:
        """One message (a service thread of its own: the controller keeps stepping). Only the node
        that serves a declared peer's negotiation may speak for it (``caller_refusal``)."""
        robot = self.negotiator.classes.robot
        try:
            message = from_ros(request)
        except (KeyError, TypeError, ValueError) as err:
            return to_ros(Message("abort", robot, "", reason=f"malformed request: {err}"[:200]), NegotiateResponse)
        if self.auth is not None:  # first: a message without the secret reaches nothing else
            refusal = self.auth.check(message)
            if refusal is not None:
                self._refused(refusal)
                return to_ros(Message("abort", robot, message.session[:200], reason=f"refused: {refusal}"),
                              NegotiateResponse)
        caller = (getattr(request, "_connection_header", None) or {}).get("callerid", "")
        refusal = caller_refusal(caller, message.sender[:100], self.peer_nodes)
        if refusal is not None:
            self._refused(refusal)
            return self._reply(Message("abort", robot, message.session[:200], reason=f"refused: {refusal}"), message)
        reply = self.negotiator.serve(message, self.strategy, self.controller, start_wait=self.timeout / 2)
        if reply.kind == "abort" and reply.reason.startswith("offer refused"):
            self._refused(f"{message.sender}: {reply.reason}")
        return self._reply(reply, message)

    def _reply(self, reply: Message, request: Message) -> NegotiateResponse:
        """Our answer, signed for the request's sender and bound to the request (with a secret)."""
        if self.auth is not None and request.sender in self.auth.secrets:
            reply = self.auth.sign(reply, request.sender, reply_to=request.nonce)
        return to_ros(reply, NegotiateResponse)

    def _hijacked(self, text: str) -> None:
        rospy.logerr("%s: %s", self.name, text)
        self.hijack = text
        self._publish()

    def _refused(self, text: str) -> None:
        """A refused message: WARN, bounded (the first ``LOGGED_REFUSALS``, then one in 1000)."""
        self.refusals += 1
        if self.refusals <= LOGGED_REFUSALS or self.refusals % 1000 == 0:
            rospy.logwarn("%s: ~negotiate: %s (%d refused so far)", self.name, text[:300], self.refusals)

    def _expire(self, _event: Any) -> None:
        """A responder's negotiation whose initiator stayed silent for 3 x timeout ends as FAILED."""
        now = time.time()
        with self.negotiator.lock:
            for peer, n in list(self.negotiator.active.items()):
                if now - n.started > 3 * self.timeout:
                    self.negotiator.expire(peer, f"{peer} went silent for more than {3 * self.timeout:g} s")

    # --- reports --------------------------------------------------------------------------------------------
    def _changed(self, n: Negotiation) -> None:
        if n.initiator and n.phase.value == "new":
            rospy.loginfo("%s: negotiation %s: starting with %s", self.name, n.session, n.peer.name)
        if n.done:
            level = rospy.loginfo if n.outcome is not None and n.outcome.adopts else rospy.logwarn
            level("%s: negotiation %s with %s: %s (%s)", self.name, n.session, n.peer.name,
                  n.outcome.value if n.outcome else "?", n.reason)
            for line in n.sent[:LOGGED_CLAUSES]:
                rospy.loginfo("%s:   sent to %s: %s", self.name, n.peer.name, line[:500])
            for line in n.received[:LOGGED_CLAUSES]:
                rospy.loginfo("%s:   received from %s: %s", self.name, n.peer.name, line[:500])
            if max(len(n.sent), len(n.received)) > LOGGED_CLAUSES:
                rospy.loginfo("%s:   (%d sent, %d received in all: ~negotiations)", self.name, len(n.sent),
                              len(n.received))
        self._publish()
        if self.on_report is not None:
            self.on_report(n)

    def _publish(self) -> None:
        reports = self.negotiator.reports()
        try:
            self.pub.publish(String(json.dumps(reports)))
            last = self.negotiator.history[-1] if self.negotiator.history else None
            if last is None:
                level, text = DiagnosticStatus.OK, "no negotiation yet"
            elif not last.done:
                level, text = DiagnosticStatus.OK, f"negotiating with {last.peer.name} ({last.phase.value})"
            elif last.outcome is not None and last.outcome.adopts:
                level, text = DiagnosticStatus.OK, f"with {last.peer.name}: {last.outcome.value}"
            else:
                level = DiagnosticStatus.ERROR if last.outcome in (Outcome.BOTH_ABORT, Outcome.ABORT_LINE_20) \
                    else DiagnosticStatus.WARN
                text = f"with {last.peer.name}: {last.outcome.value if last.outcome else '?'}: {last.reason}"
            values = [KeyValue("negotiations", str(len(reports)))]
            if last is not None:
                values += [KeyValue("peer", last.peer.name), KeyValue("session", last.session)]
                values += [KeyValue("sent", s) for s in last.sent] + [KeyValue("received", r) for r in last.received]
            status = DiagnosticStatus(level=level, name=f"{self.name}: negotiation", message=text,
                                      hardware_id=self.name, values=values)
            registration = DiagnosticStatus(
                level=DiagnosticStatus.ERROR if self.hijack else DiagnosticStatus.OK,
                name=f"{self.name}: negotiate registration", hardware_id=self.name,
                message=self.hijack or f"{self.service.resolved_name} registered to this node")
            array = DiagnosticArray(status=[status, registration])
            array.header.stamp = rospy.Time.now()
            self.diag_pub.publish(array)
        except rospy.ROSException:
            pass  # shutting down


class RegistrationWatch:
    """Checks that the master gives this node's URI for ``service`` (``lookupService``, an XML-RPC
    call bounded by ``timeout``) and registers it again when it does not: someone's
    ``registerService`` took it over (``on_hijack(text)`` is told, once per hijack). ``check`` runs in
    a timer thread; an unreachable master is tried again at the next check."""

    def __init__(self, service: Any, *, on_hijack: Callable[[str], None], timeout: float = 2.0) -> None:
        self.service = service
        self.on_hijack = on_hijack
        self.timeout = timeout
        self.hijacks = 0

    def _master(self) -> xmlrpc.client.ServerProxy:
        return timed_proxy(rosgraph.get_master_uri(), self.timeout)

    def check(self) -> bool:
        """True when the master names our service (or cannot be asked now)."""
        name, uri, node = self.service.resolved_name, self.service.uri, rospy.get_name()
        try:
            master = self._master()
            code, _, found = master.lookupService(node, name)
            if code == 1 and found == uri:
                return True
            self.hijacks += 1
            master.registerService(node, name, uri, rospy.get_node_uri())
        except (OSError, xmlrpc.client.Error):  # socket.timeout is an OSError
            return True
        self.on_hijack(f"~negotiate ({name}) was registered at the master by someone else ({found or 'nobody'}, "
                       f"not {uri}); registered it again")
        return False


def prepare_negotiation(classes: Classes, strategy: Any, timeout: float = DEFAULT_TIMEOUT,
                        auth: Authenticator | None = None) -> Negotiator | None:
    """The negotiator of a ``controller_executor`` whose mapping declares ``negotiation:``, made before
    the node starts stepping (its ``hook`` goes to ``ExecutorNode(negotiate=…)``, so a conflict at the
    first step already negotiates). Needs environment characterization (negotiation starts when it
    fails, Alg. 3 line 9): without it a warning, and None."""
    if not isinstance(strategy, ResilientStrategy):
        rospy.logwarn("%s: the mapping declares negotiation peers (%s) but environment characterization is off "
                      "(--characterize or --characterized-spec FILE): not negotiating", rospy.get_name(),
                      ", ".join(classes.peers) or "none")
        return None
    negotiator = Negotiator(classes, transport=service_transport(timeout, auth),
                            synthesis_options=strategy.characterizer.synthesis_options,
                            path=strategy.characterizer.path)
    rospy.loginfo("%s: negotiating as %s with %s (~negotiate, timeout %g s)", rospy.get_name(), classes.robot,
                  ", ".join(f"{p} ({service_of(peer)})" for p, peer in classes.peers.items()) or "nobody", timeout)
    return negotiator


__all__ = ["DEFAULT_TIMEOUT", "NegotiationEndpoint", "RegistrationWatch", "default_service", "from_ros", "prepare_negotiation",
           "service_of", "service_transport", "to_ros"]
