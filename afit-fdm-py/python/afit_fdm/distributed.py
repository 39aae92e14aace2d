"""A study spread over a Ray cluster: :func:`ray_study`.

The study's runs are split into contiguous shards; each shard is one Ray
task that flies its runs on a SIMD fleet on whichever node runs it, and
returns its table as plain data (NumPy arrays). The driver merges the shards
in run order. As run *i*'s results depend only on the study and *i*, the
merged table is the same bits as :func:`afit_fdm.study` on one machine, for
any number of shards and nodes.

Ray does all the distribution: scheduling, moving the arguments and results,
and re-running the shards of a node that is lost (``max_retries``). Ray is
imported only when :func:`ray_study` is called, so ``afit_fdm`` works
without it. Every node needs ``afit_fdm`` installed (the same version).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

from .study import Columns, PathOrText, RunTable, Study, load, shard_ranges

__all__ = ["ShardDone", "ray_study"]


@dataclass(frozen=True)
class ShardDone:
    """A finished shard, as :func:`ray_study` reports it to ``on_shard``."""

    index: int
    """The shard's position (0 for the first runs)."""
    first: int
    """Its first run."""
    end: int
    """The run after its last."""
    node_id: str
    """The Ray node that flew it (hex)."""


def _fly_shard(
    text: str, runs: int, seed: int, first: int, end: int, threads: int, precision: str
) -> Tuple[Columns, str]:
    """One shard, in a Ray worker: the study from its text, its runs flown."""
    import ray

    table = Study.from_toml(text, runs=runs, seed=seed).fly(first, end, threads=threads, precision=precision)
    return table.to_columns(), ray.get_runtime_context().get_node_id()


def ray_study(
    source: Union[Study, PathOrText],
    *,
    shards: int,
    runs: Optional[int] = None,
    seed: Optional[int] = None,
    threads: int = 1,
    precision: str = "exact",
    address: Optional[str] = None,
    max_retries: int = 3,
    scheduling_strategy: Any = "SPREAD",
    on_shard: Optional[Callable[[ShardDone], None]] = None,
) -> RunTable:
    """Flies a study (a :class:`Study`, a path or a study file's text) on a
    Ray cluster in ``shards`` contiguous shards, one Ray task each, and
    returns the merged table: the same bits as :func:`afit_fdm.study`.

    * ``threads``: threads per shard; each task asks Ray for that many CPUs.
    * ``address``: when Ray is not initialised yet, ``ray.init(address=...)``
      is called (``"auto"`` joins the cluster started with ``ray start`` on
      this machine; ``None`` starts a local Ray) and Ray is shut down again
      at the end. An initialised Ray is used as it is.
    * ``max_retries``: how many times Ray re-runs a shard whose worker or
      node died (system failures only: a study error is not retried).
    * ``scheduling_strategy``: Ray's, for each shard task (default
      ``"SPREAD"``: shards spread over the nodes).
    * ``on_shard``: called in the caller's thread as each shard finishes.
    """
    study = load(source, runs=runs, seed=seed)
    ranges = shard_ranges(study.runs, shards)
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
        raise ValueError(f"threads: {threads!r} is not a whole number of at least 1")
    if isinstance(max_retries, bool) or not isinstance(max_retries, int) or max_retries < 0:
        raise ValueError(f"max_retries: {max_retries!r} is not a whole number of at least 0")
    if precision not in ("exact", "fast"):
        raise ValueError(f"precision: {precision!r} is not 'exact' or 'fast'")
    try:
        import ray
    except ImportError as e:
        raise ImportError(f"afit_fdm.ray_study needs Ray: pip install 'afit-fdm[ray]' ({e})") from e
    started = not ray.is_initialized()
    if started:
        ray.init(address=address)
    try:
        task = ray.remote(_fly_shard).options(
            num_cpus=threads,
            max_retries=max_retries,
            retry_exceptions=False,
            scheduling_strategy=scheduling_strategy,
        )
        text = study.text
        refs = [
            task.remote(text, study.runs, study.seed, first, end, threads, precision) for first, end in ranges
        ]
        index = {ref: k for k, ref in enumerate(refs)}
        parts: Dict[int, RunTable] = {}
        pending: List[Any] = list(refs)
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            for ref in ready:
                k = index[ref]
                columns, node_id = ray.get(ref)
                parts[k] = RunTable(columns, seed=study.seed)
                if on_shard is not None:
                    first, end = ranges[k]
                    on_shard(ShardDone(k, first, end, node_id))
        return RunTable.concat([parts[k] for k in range(len(ranges))])
    finally:
        if started:
            ray.shutdown()
