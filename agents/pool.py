"""The session's agents (MASSRIS section 5): a fixed number, each idle or given a task
by the manager. Tasks take agents from the pool and hand them back when they end."""


class AgentPool:
    """The idle agents' ids, taken last-in first-out (the order tasks get them in is
    part of a run's outcome: it is deterministic)."""

    def __init__(self, size):
        self.size = int(size)
        self._free = list(range(self.size))

    def __len__(self):
        """Idle agents."""
        return len(self._free)

    @property
    def busy(self):
        return self.size - len(self._free)

    def take(self, k=1):
        """k idle agents' ids (the caller checked there are that many)."""
        if k > len(self._free):
            raise ValueError(f"{k} agents asked for, {len(self._free)} idle")
        return [self._free.pop() for _ in range(k)]

    def give_back(self, ids):
        """Agents whose task ended (ids < 0 stand for none and are skipped)."""
        self._free.extend(int(a) for a in ids if a >= 0)
