"""The small toolkit every ltl_stack command-line tool shares: one exit-code table
(``ltl_stack.errors.Exit``), one message style, one meaning of ``--json``, and outputs that never
overwrite an input.

Conventions (the README's "Tools" section describes them to users):

* errors: ``<tool>: error: <file>:<line>: <message>`` on stderr, one line, no traceback;
* warnings: ``<tool>: warning: <message>``; progress: ``<tool>: <message>`` (stderr);
* ``--json``: the tool's machine-readable result on **stdout** (never a file path);
* output files are written atomically (``ltl_stack.fileio.write_atomic``) and only once every check
  has passed; an output that names an input (same file, also through links) is refused with exit 2.
"""
from __future__ import annotations

import argparse
import codecs
import errno
import gc
import json
import math
import os
import sys
import tempfile
import threading
from collections.abc import Callable, Iterable
from typing import Any, NoReturn, TextIO

from ltl_stack import stdstreams
from ltl_stack.errors import Exit, OutputError, UserError, exit_codes_epilog
from ltl_stack.fileio import output_refusal, write_atomic


class ToolParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` whose epilog lists the tool's exit codes from the one table.

    A usage error is one line ``<tool>: error: … (see <tool> --help)`` on stderr and exit
    ``Exit.BAD_INPUT`` (argparse's own 2; its usage block is left out: every error is one line),
    ``--help`` prints help and exits 0 without doing anything else.
    """

    def __init__(self, prog: str, description: str, exit_codes: Iterable[Exit] = (), epilog: str = "",
                 **kwargs: Any):
        codes = tuple(exit_codes) or (Exit.OK, Exit.BAD_INPUT)
        text = (epilog + "\n\n" if epilog else "") + exit_codes_epilog(*codes)
        kwargs.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(prog=prog, description=description, epilog=text, **kwargs)

    def error(self, message: str) -> NoReturn:
        """A usage error: one line on stderr, exit 2."""
        self.exit(int(Exit.BAD_INPUT), f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def print_help(self, file: TextIO | None = None) -> None:
        """Help on stdout; a closed pipe ends quietly, a full disk or a closed stdout with one error
        line (exit 4)."""
        try:
            if file is None and stdstreams.STDOUT_CLOSED:
                raise OSError(errno.EBADF, "standard output is closed")
            super().print_help(file)
            (file or sys.stdout).flush()
        except OSError as err:
            self.exit(_output_failed(self.prog, err, file or sys.stdout))

    def add_json(self, what: str = "the result") -> None:
        """The shared ``--json`` flag: ``what`` as JSON on stdout instead of text."""
        self.add_argument("--json", action="store_true", help=f"print {what} as JSON on stdout")


def error(prog: str, message: str, stream: TextIO | None = None) -> None:
    """Print the one error line of a tool (a message that starts with the tool's name, as a node's
    ``[FATAL]`` line does, does not repeat it)."""
    if message.startswith(f"{prog}: "):
        message = message[len(prog) + 2:]
    print(f"{prog}: error: {message}", file=stream or sys.stderr, flush=True)


def warn(prog: str, message: str, stream: TextIO | None = None) -> None:
    """Print a warning line of a tool."""
    print(f"{prog}: warning: {message}", file=stream or sys.stderr, flush=True)


def say(prog: str, message: str, stream: TextIO | None = None) -> None:
    """Print a progress/information line of a tool (stderr, so stdout stays the result)."""
    print(f"{prog}: {message}", file=stream or sys.stderr, flush=True)


def print_json(data: Any) -> None:
    """The ``--json`` result on stdout, one document, flushed."""
    sys.stdout.write(json.dumps(data, indent=1, sort_keys=False) + "\n")
    sys.stdout.flush()


class StdoutFailed(OSError):
    """Writing or flushing a tool's stdout failed (the original ``OSError`` in ``error``), told apart
    from the tool's other ``OSError``s; still an ``OSError`` for code that handles those."""

    def __init__(self, error: OSError) -> None:
        super().__init__(error.errno, error.strerror)
        self.error = error


class _CheckedStdout:
    """``sys.stdout`` while a tool runs (``run``): whole lines, and a failed write or flush raises
    ``StdoutFailed``, as does any write when the tool was started with its stdout closed (``tool >&-``).

    ``print`` writes the text and the newline in two calls, so lines printed by two threads (ROS
    callbacks, timers and the main loop) could interleave, and a ``--json`` reader get two documents on
    one line. Text is kept per thread until its newline (or a flush: a prompt), and complete lines are
    written under a lock."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self._lock = threading.Lock()
        self._local = threading.local()

    def write(self, text: str) -> int:
        if text and stdstreams.STDOUT_CLOSED:
            raise StdoutFailed(OSError(errno.EBADF, "standard output is closed"))
        pending = self._pending()
        cut = text.rfind("\n") + 1
        if cut:
            lines = "".join(pending) + text[:cut]
            pending.clear()
            self._send(lines, flush=False)
        if cut < len(text):
            pending.append(text[cut:])
        return len(text)

    def flush(self) -> None:
        self._send(self._take(), flush=True)

    def _pending(self) -> list[str]:
        """The calling thread's text since its last newline, in pieces (joined once: linear)."""
        return self._local.__dict__.setdefault("pending", [])

    def _take(self) -> str:
        pending = self._pending()
        text = "".join(pending)
        pending.clear()
        return text

    def _send(self, text: str, flush: bool) -> None:
        with self._lock:
            try:
                if text:
                    self.stream.write(text)
                if flush:
                    self.stream.flush()
            except OSError as err:
                raise StdoutFailed(err) from None

    def leave(self) -> None:
        """The calling thread's unfinished line to the stream as it is (a tool ending on an error)."""
        try:
            self.stream.write(self._take())
        except (OSError, ValueError):
            pass

    def __getattr__(self, name: str) -> Any:
        return getattr(self.stream, name)


def _output_failed(prog: str, err: OSError, stream: TextIO) -> int:
    """After a failed write to ``stream``: send what is still buffered to /dev/null (so the exit does
    not fail again) and give the exit code. A closed pipe (``tool | head``) is not an error; anything
    else (a full disk) is one error line and ``Exit.WRITE_FAILED``."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass
    if isinstance(err, BrokenPipeError):
        return int(Exit.OK)
    error(prog, f"cannot write the output: {err.strerror or err}")
    return int(Exit.WRITE_FAILED)


def _path_bytes(err: UnicodeError) -> tuple[str | bytes, int]:
    """Encoding error handler of a tool's stdout: a file name given on the command line that is not
    UTF-8 (byte 0xff arrives as the lone surrogate U+DCFF) is written back as its own bytes, anything else the
    encoding cannot write as a backslash escape."""
    if isinstance(err, UnicodeEncodeError):
        part = err.object[err.start:err.end]
        if all("\udc80" <= c <= "\udcff" for c in part):
            return bytes(ord(c) - 0xDC00 for c in part), err.end
    return codecs.backslashreplace_errors(err)


codecs.register_error("ltl_stack_path", _path_bytes)


def _print_any_path(stream: TextIO) -> None:
    """Let ``stream`` print any text: with ``PYTHONIOENCODING=utf-8`` or a UTF-8 locale stdout is
    strict, and printing a non-UTF-8 file name given as an argument ended in UnicodeEncodeError."""
    reconfigure = getattr(stream, "reconfigure", None)
    if reconfigure is not None:
        try:
            reconfigure(errors="ltl_stack_path")
        except (ValueError, OSError):
            pass


def run(prog: str, body: Callable[[], int | None]) -> int:
    """Run a tool's body and turn every ``UserError`` into its one line and exit code.

    ``KeyboardInterrupt`` exits 130 quietly; a closed stdout (``tool | head``) is not an error; stdout
    that cannot be written (a full disk) is one error line and ``Exit.WRITE_FAILED``, also when the
    failure shows only as the buffered output is flushed at the end.
    """
    stdout = sys.stdout
    _print_any_path(stdout)
    sys.stdout = checked = _CheckedStdout(stdout)
    try:
        code = body()
        sys.stdout.flush()
        return int(Exit.OK if code is None else code)
    except UserError as e:
        error(prog, str(e))
        return int(e.code)
    except KeyboardInterrupt:
        return int(Exit.INTERRUPTED)
    except StdoutFailed as e:
        return _output_failed(prog, e.error, stdout)
    except BrokenPipeError as e:  # stdout written through a reference taken before ``run``
        return _output_failed(prog, e, stdout)
    finally:
        sys.stdout = stdout
        checked.leave()


def imports_done() -> None:
    """Call in a tool's script once its modules are imported, when the script disabled the cyclic
    garbage collector (``gc.disable()``) before importing them: the objects created so far (modules,
    classes, functions: alive until the process ends) are moved out of the collector's sight
    (``gc.freeze``) and collection is enabled again. Collecting while ~200 modules load took ~4 ms
    of a ``synthesize`` run, and later collections no longer walk those objects."""
    gc.freeze()
    gc.enable()


def exit_now(code: int) -> NoReturn:
    """End a tool's process with ``code`` right away, without Python's interpreter teardown
    (unloading every module and freeing every object one by one: ~9 ms of a ``synthesize`` run
    that takes ~60 ms). For scripts only, after the tool's ``main`` has returned: outputs are
    written and closed by then (``write_outputs``); log handlers (``logging.shutdown``, the exit job
    a loaded module registers) and stdout and stderr are flushed here. When that flush fails, or
    another thread still runs, the ordinary exit is taken (it reports and waits as Python does).
    Other ``atexit`` jobs are not run: a tool that registers one must not use this."""
    try:
        logging = sys.modules.get("logging")
        if logging is not None:
            logging.shutdown()
        sys.stdout.flush()
        sys.stderr.flush()
    except BaseException:
        sys.exit(code)
    if threading.active_count() > 1 and any(not t.daemon for t in threading.enumerate()
                                            if t is not threading.main_thread()):
        sys.exit(code)
    os._exit(code)


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def check_outputs(inputs: Iterable[str | os.PathLike | None], outputs: Iterable[str | os.PathLike | None]) -> None:
    """Refuse (``OutputError``, exit 2) an output path that is one of the inputs, also through links
    or another spelling of the path, two outputs that are one file, and an output naming something
    that is not a regular file or a new path (a FIFO, a device, a folder: ``output_refusal``).
    ``None`` entries are skipped.

    Call before any work is written, so a refused call leaves every file as it was.
    """
    ins = [os.fspath(p) for p in inputs if p is not None]
    outs = [os.fspath(p) for p in outputs if p is not None]
    for out in outs:
        refusal = output_refusal(out)
        if refusal:
            raise OutputError(f"{out}: cannot be an output: {refusal}; choose a file path")
        for inp in ins:
            if _same_file(out, inp):
                raise OutputError(f"{out}: output would overwrite the input {inp}; choose another output path")
    for i, out in enumerate(outs):
        for other in outs[i + 1:]:
            if _same_file(out, other):
                raise OutputError(f"{out}: named for two outputs ({other}); choose distinct output paths")


def write_output(path: str | os.PathLike, data: str | bytes, what: str = "output", mode: int | None = None) -> None:
    """Write an output atomically; a failure is ``OutputError`` with ``Exit.WRITE_FAILED`` and no file left.

    ``mode``: the new file's permissions (default: a new file's under the umask).
    """
    try:
        write_atomic(path, data, mode)
    except OSError as e:
        raise OutputError(f"{path}: cannot write the {what}: {e.strerror or e}", Exit.WRITE_FAILED) from None



def write_outputs(outputs: Iterable[tuple[str | os.PathLike, str | bytes, str]]) -> None:
    """Write several outputs ``(path, data, what)`` all or none: each goes to a temporary file next
    to its target first; only when every one is written are they renamed into place. A failure is
    ``OutputError`` (``Exit.WRITE_FAILED``) and leaves no file behind and every target as it was."""
    staged: list[tuple[str, str]] = []
    try:
        for path, data, what in outputs:
            target = os.fspath(path)
            raw = data.encode("utf-8") if isinstance(data, str) else data
            refusal = output_refusal(target)
            if refusal:
                raise OutputError(f"{target}: cannot write the {what}: {refusal}", Exit.WRITE_FAILED)
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", dir=os.path.dirname(target) or ".")
                staged.append((tmp, target))
                with os.fdopen(fd, "wb") as f:
                    f.write(raw)
                umask = os.umask(0)
                os.umask(umask)
                os.chmod(tmp, 0o666 & ~umask)
            except OSError as e:
                raise OutputError(f"{target}: cannot write the {what}: {e.strerror or e}", Exit.WRITE_FAILED) from None
        for tmp, target in staged:
            try:
                os.replace(tmp, target)
            except OSError as e:
                raise OutputError(f"{target}: cannot write: {e.strerror or e}", Exit.WRITE_FAILED) from None
    finally:
        for tmp, _ in staged:
            if os.path.exists(tmp):
                os.unlink(tmp)

# Option types for numbers (``type=`` of ``add_argument``): a value that is not a finite number in
# range is a usage error (exit 2) with one short line, also for ``nan``, ``inf`` and integers longer
# than Python converts.

#: digits an integer option may have; longer ones are refused before ``int()`` (Python's own limit
#: is 4300 digits, and its message repeats the whole number)
MAX_OPTION_DIGITS = 18


#: the highest rate (Hz) any rate or frequency of ltl_stack takes, as an option or a node's ``~param``:
#: a faster loop only spins a core (``_rate:=1e17``), and nothing here needs more than a kHz
MAX_RATE = 1000.0

#: the smallest positive time or rate an option takes (ROS' clock counts nanoseconds; the inverse
#: of a smaller rate overflows it)
SMALLEST_OPTION = 1e-9


def _shown(text: str) -> str:
    return repr(text if len(text) <= 24 else text[:20] + "…")


def _number(text: str, kind: type, minimum: float, strict: bool) -> float | int:
    word = "an integer" if kind is int else "a number"
    bound = f"{'>' if strict else '>='} {minimum:g}"
    value: float | int | None = None
    digits = text.strip().lstrip("+-")
    if kind is int:
        if digits.isdigit() and len(digits) > MAX_OPTION_DIGITS:
            raise argparse.ArgumentTypeError(f"{_shown(text)} has {len(digits)} digits (at most "
                                             f"{MAX_OPTION_DIGITS})")
        if digits.isdigit():
            value = int(text)
    elif len(text) <= 64:
        try:
            value = float(text)
        except ValueError:
            value = None
    if value is None or not math.isfinite(value) or value < minimum or (strict and value == minimum):
        raise argparse.ArgumentTypeError(f"{_shown(text)} is not {word} {bound}")
    if abs(value) >= 10 ** MAX_OPTION_DIGITS:
        raise argparse.ArgumentTypeError(f"{_shown(text)} has more than {MAX_OPTION_DIGITS} digits")
    if kind is float and 0 < value < SMALLEST_OPTION:
        raise argparse.ArgumentTypeError(f"{_shown(text)} is not 0 and below {SMALLEST_OPTION:g} (a time or rate "
                                         "that small is 0 for ROS' clock)")
    return value


def positive_float(text: str) -> float:
    """Option type: a finite number > 0 (a rate, a duration that must pass)."""
    return float(_number(text, float, 0.0, True))


def non_negative_float(text: str) -> float:
    """Option type: a finite number >= 0 (a timeout or duration where 0 means "none")."""
    return float(_number(text, float, 0.0, False))


def rate_or_zero(text: str) -> float:
    """Option type: a rate in Hz, 0 (off) or finite and at most ``MAX_RATE``."""
    value = float(_number(text, float, 0.0, False))
    if value > MAX_RATE:
        raise argparse.ArgumentTypeError(f"{_shown(text)} is above {MAX_RATE:g} Hz (the highest rate ltl_stack "
                                         "takes: a faster loop only spins a core)")
    return value


def non_negative_int(text: str) -> int:
    """Option type: an integer >= 0 (a count where 0 means "no limit" or "none")."""
    return int(_number(text, int, 0, False))


def positive_int(text: str) -> int:
    """Option type: an integer >= 1."""
    return int(_number(text, int, 1, False))
