"""Everything in the HAL, as dicts: LinuxCNC 2.10's `hal.query`.

Each description is a dict whose first key, `haltype`, says what it
describes:

* `pin`: name, type (`hal.Type`), dir (`hal.Dir`), value, alias (the
  name before `alias`, or None), signal (or None), comp, comp_id
* `parameter`: as a pin, without `signal`
* `signal`: name, type, value, writers, readers, bidirs, driver (the
  output pin's name, or None)
* `component`: name, type (`hal.CompType`), id, pid (0 for realtime
  ones), ready, insmod (the `loadrt` arguments, or None)
* `function`: name, comp, comp_id, users, reentrant
* `thread`: name, comp, comp_id, priority, period (ns), functions (a list
  of `threadfunction` dicts: name, index, is_init)

`pins()`, `params()`, `signals()`, `comps()`, `functs()` and `threads()`
return every one, in a dict by name; `pin(name)`, `param(name)`,
`signal(name)`, `comp(name or id)`, `funct(name)`, `thread(name)` one, and
`signalpins(name)` the pins linked to a signal. A name that is not there
gives None. The instance is the one `HAL_INSTANCE` names; if no HAL runs
there, RuntimeError says so.

    import hal
    print(hal.query.comp("and2"))
    for name, sig in hal.query.signals().items():
        print(name, sig["value"], sig["driver"])
"""

from . import CompType, Dir, Type, _hal

__all__ = [
    "pin",
    "param",
    "signal",
    "comp",
    "funct",
    "thread",
    "signalpins",
    "pins",
    "params",
    "signals",
    "comps",
    "functs",
    "threads",
]


def _tagged(d):
    """The dict with its type and direction numbers as enum members (in
    place, so the keys keep their order)."""
    if d is None:
        return None
    if "type" in d:
        kind = CompType if d["haltype"] == "component" else Type
        d["type"] = kind(d["type"])
    if "dir" in d:
        d["dir"] = Dir(d["dir"])
    return d


def _all_tagged(by_name):
    if by_name is None:
        return None
    for d in by_name.values():
        _tagged(d)
    return by_name


def _name(what, name):
    """Checks that a lookup got a name, saying which lookup did not."""
    if not isinstance(name, str):
        raise TypeError(
            "hal.query.%s: the name must be a str, not %s" % (what, type(name).__name__)
        )
    return name


def pin(name):
    """The pin named `name` (or its name before `alias`), or None."""
    return _tagged(_hal._query_pin(_name("pin", name)))


def param(name):
    """The param named `name` (or its name before `alias`), or None."""
    return _tagged(_hal._query_param(_name("param", name)))


def signal(name):
    """The signal named `name`, or None."""
    return _tagged(_hal._query_signal(_name("signal", name)))


def comp(key):
    """The component named `key` (str) or with id `key` (int), or None."""
    if isinstance(key, bool) or not isinstance(key, (str, int)):
        raise TypeError(
            "hal.query.comp: a component is named by str or int id, not %s"
            % type(key).__name__
        )
    return _tagged(_hal._query_comp(key))


def funct(name):
    """The function named `name`, or None."""
    return _hal._query_funct(_name("funct", name))


def thread(name):
    """The thread named `name` with its functions, or None."""
    return _hal._query_thread(_name("thread", name))


def signalpins(name):
    """The pins linked to signal `name`, by name; None if there is no such
    signal."""
    return _all_tagged(_hal._query_signalpins(_name("signalpins", name)))


def pins():
    """Every pin, by name (in name order)."""
    return _all_tagged(_hal._query_pins())


def params():
    """Every param, by name (in name order)."""
    return _all_tagged(_hal._query_params())


def signals():
    """Every signal, by name (in name order)."""
    return _all_tagged(_hal._query_signals())


def comps():
    """Every component, by name, newest first."""
    return _all_tagged(_hal._query_comps())


def functs():
    """Every function, by name (in name order)."""
    return _hal._query_functs()


def threads():
    """Every thread with its functions, by name, slowest first."""
    return _hal._query_threads()
