"""The order of a kernel's intermediates for compiled code: few values alive at once.

GCC at ``-O2`` on x86-64 keeps the statement order of straight-line code (it schedules only
after register allocation), so the order of the assignments decides how many values are alive
at once, hence how many go to the stack and come back, and how many register copies the
two-operand SSE arithmetic needs.  A kernel built by sweeps (one tangent sweep per joint, all
outputs at the end) keeps every finished entry alive to the end of the function.

:func:`scheduled` reorders the assignments by a greedy list scheduler (Sethi–Ullman's aim,
for a DAG): among the intermediates whose operands are all computed, take the one that reads
the most values for the last time, ties to the earliest in the given order; an output entry is
stored as soon as everything it reads is computed (``Kernel.early_stores``: the C template
writes each entry right after the last intermediate it reads), so it ends its values' lives
too.  Only the order changes (and the names ``t0, t1, ...`` follow it): every intermediate
is the same expression, every result the same number.
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence
from dataclasses import replace

import sympy as sp

from symkin.kernels.rename import renamed, renamed_matrix
from symkin.kernels.spec import Kernel, intermediate_prefix


def scheduled(kernel: Kernel) -> Kernel:
    """``kernel`` with its assignments in a low-pressure order (module doc), renamed
    ``t0, t1, ...`` in that order, and ``early_stores`` set."""
    index = {s: k for k, (s, _) in enumerate(kernel.assignments)}
    reads = [_reads(e, index) for _, e in kernel.assignments]
    entries = [_reads(e, index) for o in kernel.outputs for e in o.matrix]
    old = [kernel.assignments[k] for k in greedy_order(reads, entries)]
    prefix = intermediate_prefix([s for i in kernel.inputs for s in i.symbols])
    renaming = {s: sp.Symbol(f"{prefix}{k}", real=True) for k, (s, _) in enumerate(old)}
    memo: dict = {}
    return replace(
        kernel,
        assignments=tuple((renaming[s], renamed(e, renaming, memo)) for s, e in old),
        outputs=tuple(
            replace(o, matrix=renamed_matrix(o.matrix, renaming, memo)) for o in kernel.outputs
        ),
        early_stores=True,
    )


def _reads(expr: sp.Expr, index: dict[sp.Symbol, int]) -> tuple[int, ...]:
    return tuple(sorted(index[s] for s in expr.free_symbols if s in index))


def greedy_order(reads: Sequence[Sequence[int]], entries: Sequence[Sequence[int]]) -> list[int]:
    """An evaluation order of assignments ``0 .. n-1`` (``reads[k]``: the earlier ones
    assignment ``k`` reads; ``entries``: what each output entry reads).

    Score of a ready assignment: how many values it reads for the last time (entries stored as
    soon as ready count as readers); the highest goes next, ties to the lowest index, so an
    order that is already good is kept where nothing is gained.
    """
    state = _Scheduler(reads, entries)
    order: list[int] = []
    while state.ready:
        negative, k = heapq.heappop(state.ready)
        if not state.placed[k] and -negative == state.score[k]:  # else a stale heap entry
            state.place(k)
            order.append(k)
    return order


class _Scheduler:
    """The bookkeeping of :func:`greedy_order`: readers left per value, operands not yet
    computed per assignment and entry, scores, and the heap of ready assignments."""

    def __init__(self, reads: Sequence[Sequence[int]], entries: Sequence[Sequence[int]]):
        self.reads, self.entries = reads, entries
        self.users: list[list[int]] = [[] for _ in reads]  # assignments reading k
        self.stores: list[list[int]] = [[] for _ in reads]  # entries reading k
        for k, operands in enumerate(reads):
            for j in operands:
                self.users[j].append(k)
        for e, operands in enumerate(entries):
            for j in operands:
                self.stores[j].append(e)
        self.remaining = [len(u) + len(s) for u, s in zip(self.users, self.stores, strict=True)]
        self.waiting = [len(r) for r in reads]
        self.entry_waiting = [len(r) for r in entries]
        self.placed = [False] * len(reads)
        # an operand whose only reader is k: k ends its life
        self.score = [sum(1 for j in r if self.remaining[j] == 1) for r in reads]
        self.ready = [(-self.score[k], k) for k in range(len(reads)) if not reads[k]]
        heapq.heapify(self.ready)

    def place(self, k: int) -> None:
        self.placed[k] = True
        for j in self.reads[k]:
            self._read_once(j)
        for e in self.stores[k]:
            self.entry_waiting[e] -= 1
            if self.entry_waiting[e] == 0:  # stored now
                for j in self.entries[e]:
                    self._read_once(j)
        for u in self.users[k]:
            self.waiting[u] -= 1
            if not self.waiting[u]:
                heapq.heappush(self.ready, (-self.score[u], u))

    def _read_once(self, j: int) -> None:
        """One reader of ``j`` is done; the last one left, if an assignment, scores a kill."""
        self.remaining[j] -= 1
        if self.remaining[j] == 1:
            for k in self.users[j]:
                if not self.placed[k]:
                    self.score[k] += 1
                    if not self.waiting[k]:
                        heapq.heappush(self.ready, (-self.score[k], k))
