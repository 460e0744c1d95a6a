"""The maps of musclesim.batch.cluster, without a cluster: `dask_map` over a stand-in client."""
from musclesim.batch import dask_map, serial_map


class FakeClient:
    """What `dask_map` uses of a Dask client: map (futures) and gather (their results)."""

    def __init__(self):
        self.mapped = []

    def map(self, fn, items, pure=True):
        assert pure is False  # tasks are never taken from a cache
        self.mapped.append(list(items))
        return [fn(x) for x in items]

    def gather(self, futures):
        return list(futures)


def test_dask_map_keeps_the_order_and_runs_a_single_item_here():
    client = FakeClient()
    pmap = dask_map(client)
    assert pmap(lambda x: x * x, iter([3, 1, 2])) == [9, 1, 4]
    assert pmap(lambda x: -x, [5]) == [-5] and pmap(abs, []) == []
    assert client.mapped == [[3, 1, 2]]  # one and zero items did not go to the cluster


def test_serial_map():
    assert serial_map(lambda x: x + 1, (1, 2)) == [2, 3]
