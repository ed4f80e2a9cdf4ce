"""`linuxcnc.ini`: a machine's INI file, read as the launcher reads it."""

from hal import _hal

from ._errors import error


class ini:  # noqa: N801  (LinuxCNC's name)
    """The INI file at `path` (`linuxcnc.error` if it cannot be read)."""

    def __init__(self, path):
        try:
            self._entries = _hal._ini_entries(str(path))
        except OSError as e:
            raise error("inifile.open() failed: %s" % e) from e

    def find(self, section, key, num=1):
        """The `num`th value (from 1) of `key` in `section`, else None."""
        if not isinstance(num, int):
            raise TypeError("num must be an integer, not %r" % type(num).__name__)
        found = self.findall(section, key)
        if 1 <= num <= len(found):
            return found[num - 1]
        return None

    def findall(self, section, key):
        """Every value of `key` in `section`, in file order."""
        return [v for s, k, v in self._entries if s == section and k == key]
