"""`linuxcnc.ini`: a machine's INI file, read as the launcher reads it."""

from hal import _hal


class ini:  # noqa: N801  (LinuxCNC's name)
    """The INI file at `path` (OSError if it cannot be read)."""

    def __init__(self, path):
        self._entries = _hal._ini_entries(str(path))

    def find(self, section, key, default=None):
        """The first value of `key` in `section`, else `default`."""
        for s, k, v in self._entries:
            if s == section and k == key:
                return v
        return default

    def findall(self, section, key):
        """Every value of `key` in `section`, in file order."""
        return [v for s, k, v in self._entries if s == section and k == key]
