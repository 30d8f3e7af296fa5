"""Credentials of ``launch --secure`` systems (pure: files, no zenoh).

The supervisor makes a random password for each node and one for local clients, writes the
router's list of users (``user:password`` lines, readable by the user only) in a private
folder of its own, and the clients' entry into the per-user credentials file, keyed by the
router's endpoint: ``$TURTLECTL_CREDENTIALS``, else ``~/.turtlectl/credentials.json`` (also
readable by the user only).  Every client command reads that file and logs in with the
entry for its ``--connect`` endpoint; the supervisor removes its entry when it stops.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import tempfile
from pathlib import Path

import msgspec

from turtlectl.messages.keys import name_chunk
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.config import Credentials

ENV = "TURTLECTL_CREDENTIALS"
ROLE_ENV = "TURTLECTL_ROLE"  # which of the system's client logins a command uses
DEFAULT_ROLE = "operator"


ROLES = ("viewer", "operator", "teleop")


def role() -> str:
    """The role a client command logs in as: $TURTLECTL_ROLE, else operator (BadInput if it
    names no role)."""
    chosen = os.environ.get(ROLE_ENV, "").strip() or DEFAULT_ROLE
    if chosen not in ROLES:
        raise BadInput(f"{ROLE_ENV}={chosen!r} is not a role (roles: {', '.join(ROLES)})")
    return chosen


def store_path() -> Path:
    """The per-user credentials file: $TURTLECTL_CREDENTIALS, else ~/.turtlectl/credentials.json."""
    named = os.environ.get(ENV)
    return Path(named) if named else Path.home() / ".turtlectl" / "credentials.json"


def where_none(endpoint: str) -> str:
    """Where a client looked for its login for ``endpoint`` and found none, for the message
    of a refused client: the default file (then $TURTLECTL_CREDENTIALS is worth knowing), or
    the file the variable names (then it is set already, and may name no file at all)."""
    path = store_path()
    if not os.environ.get(ENV):
        return f"{path} has none for {endpoint} (or set {ENV})"
    if not path.exists():
        return f"{ENV} names {path}, which does not exist"
    return f"{path} ({ENV}) has none for {endpoint}"


def new_credentials(user: str) -> Credentials:
    """``user`` with a random password (32 URL-safe characters, 192 bits)."""
    return Credentials(user=user, password=secrets.token_urlsafe(24))


#: how a node's login is keyed in a system's entry of the credentials file (beside the roles)
NODE_ENTRY = "node {}"


def node_user(name: str) -> str:
    """The login of node ``name`` (its full name as one chunk: ``node-turtle2.navigator``)."""
    return f"node-{name_chunk(name)}"


def _write_private(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` readable and writable by the user only, replacing it whole."""
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")  # 0600 from the start
    try:
        with os.fdopen(fd, "w") as out:
            out.write(text)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


def write_users(folder: Path, users: list[Credentials]) -> Path:
    """The router's list of users (Zenoh's ``dictionary_file``) in ``folder``."""
    path = folder / "users.txt"
    _write_private(path, "".join(f"{c.user}:{c.password}\n" for c in users))
    return path


Logins = dict[str, Credentials]  # role -> its login


def _entries(path: Path) -> dict[str, Logins]:
    """The file's entries ({} if there is none); BadInput if it cannot be used (never
    overwritten then: the other systems' logins are in it)."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return {}
    except OSError as exc:
        raise BadInput(f"cannot read the credentials file {path}: {exc.strerror or exc}") from None
    try:
        return msgspec.json.decode(data, type=dict[str, Logins])
    except msgspec.DecodeError as exc:
        raise BadInput(f"the credentials file {path} is not one turtlectl wrote ({exc}): move it away") from None


def publish(endpoint: str, logins: Logins, path: Path | None = None) -> Path:
    """Make ``logins`` (by role) the clients' logins for the router at ``endpoint``."""
    path = path or store_path()
    entries = _entries(path)
    entries[endpoint] = logins
    _write_private(path, msgspec.json.encode(entries).decode())
    return path


def withdraw(endpoint: str, path: Path | None = None) -> None:
    """Forget the clients' login for ``endpoint`` (its system stopped)."""
    path = path or store_path()
    entries = _entries(path)
    if entries.pop(endpoint, None) is not None:
        _write_private(path, msgspec.json.encode(entries).decode())


def entry_text(endpoint: str, path: Path | None = None) -> bytes:
    """A credentials file holding only the system at ``endpoint``'s entry (its roles' logins and
    those of its nodes that run on other hosts), for another host; BadInput if there is none."""
    path = path or store_path()
    entry = _entries(path).get(endpoint)
    if entry is None:
        raise BadInput(f"{path} has no entry for {endpoint}: is a `launch --secure` system running there?")
    return msgspec.json.encode({endpoint: entry})


def node_login(endpoint: str, name: str, path: Path | None = None) -> Credentials | None:
    """The login a ``launch --secure`` system at ``endpoint`` made for its node ``name`` that
    runs on another host (``launch --exclude``), if the credentials file has it."""
    return _entries(path or store_path()).get(endpoint, {}).get(NODE_ENTRY.format(name))


def for_endpoint(endpoint: str, path: Path | None = None, as_role: str | None = None) -> Credentials | None:
    """The login of ``as_role`` (default: ``role()``) for the router at ``endpoint``, if a
    --secure system published one."""
    return _entries(path or store_path()).get(endpoint, {}).get(as_role or role())
