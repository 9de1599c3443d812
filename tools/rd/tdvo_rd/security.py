"""Who can reach the Dask scheduler runs code on every worker: Dask sends pickled functions, so a
scheduler that accepts plain `tcp://` connections from a network gives that network the workers'
accounts. 3dvo-rd starts no scheduler and binds no port itself; it is the client. It helps the
user not to expose one: plain TCP to a scheduler that is not on this machine is warned about
(docs/rd.md, "Security"), and TLS client certificates (`--tls-ca-file`, `--tls-cert`,
`--tls-key`) are passed to Dask's own security options (distributed.security.Security)."""

import ipaddress
import json
import os
from urllib.parse import urlsplit

LOOPBACK_NAMES = {"localhost", "localhost.localdomain", "ip6-localhost", "ip6-loopback"}


def scheduler_address(scheduler):
    """The address of `scheduler`: itself, or the "address" of a scheduler file (None when the
    file cannot be read: Dask reports that)."""
    if os.path.isfile(scheduler):
        try:
            with open(scheduler, encoding="utf-8") as f:
                address = json.load(f).get("address")
        except (OSError, ValueError, AttributeError):
            return None
        return address if isinstance(address, str) else None
    return scheduler


def check_scheduler(scheduler):
    """Raises ValueError, naming the problem in one line, when `scheduler` (--scheduler) names
    no scheduler: an empty address, or a file that is not a scheduler file (a JSON object with
    an "address" string, as `dask scheduler --scheduler-file` writes)."""
    if not scheduler.strip():
        raise ValueError("--scheduler: empty address (leave the option out to run on the local "
                         "pool)")
    if not os.path.isfile(scheduler):
        return
    try:
        with open(scheduler, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as e:
        raise ValueError("%s: cannot read the scheduler file (%s)" % (scheduler, e.strerror))
    except ValueError as e:
        raise ValueError("%s: not a Dask scheduler file (%s)" % (scheduler, e))
    address = data.get("address") if isinstance(data, dict) else None
    if not isinstance(address, str) or not address.strip():
        raise ValueError("%s: not a Dask scheduler file (no \"address\" string)" % scheduler)


def is_loopback(host):
    if host is None:
        return False
    if host.lower() in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def insecure_scheduler_warning(scheduler, tls=False):
    """A warning (one line) when jobs would go over plain TCP to a scheduler on another machine,
    None otherwise (a loopback address, an SSH tunnel's local end, a tls:// address, or TLS
    options given)."""
    address = scheduler_address(scheduler)
    if not address or tls:
        return None
    parts = urlsplit(address if "://" in address else "tcp://" + address)
    if parts.scheme not in ("tcp", "ws", ""):
        return None  # tls://, wss:// or inproc://
    if is_loopback(parts.hostname):
        return None
    return ("3dvo-rd: warning: the Dask scheduler %s is reached over plain TCP: anyone who can "
            "connect to it can run code on every worker. Use TLS (--tls-ca-file, --tls-cert, "
            "--tls-key and a tls:// scheduler) or an SSH tunnel to 127.0.0.1 (docs/rd.md, "
            "\"Security\")" % address)


def tls_options(ca_file, cert, key):
    """Checks the TLS options (all three or none) and returns them as a tuple, or None."""
    given = [v for v in (ca_file, cert, key) if v]
    if not given:
        return None
    if len(given) != 3:
        raise ValueError("--tls-ca-file, --tls-cert and --tls-key go together: give all three")
    for v in (ca_file, cert, key):
        if not os.path.isfile(v):
            raise ValueError("%s: no such file" % v)
    return (ca_file, cert, key)


def make_security(tls):
    """distributed's Security for the client, requiring encryption; None without TLS options."""
    if not tls:
        return None
    from distributed.security import Security
    ca_file, cert, key = tls
    return Security(tls_ca_file=ca_file, tls_client_cert=cert, tls_client_key=key,
                    require_encryption=True)
