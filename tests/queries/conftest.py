"""Fixtures of the query tests."""
import pytest


class Built(list):
    """The objects closest-point Projectors were built for; ``forget(obj)`` drops the
    cached projectors of ``obj`` (identity and content entries), so it is built again."""

    def forget(self, obj):
        from cagd.queries import closest as cl
        cl._CACHE.pop(obj, None)
        cl._BY_CONTENT.clear()


@pytest.fixture
def projectors_built(monkeypatch):
    """:class:`Built`, filled by every Projector built from now on."""
    from cagd.queries import closest as cl
    built = Built()
    real = cl.Projector.__init__

    def spy(self, obj, *a, **kw):
        built.append(obj)
        real(self, obj, *a, **kw)

    monkeypatch.setattr(cl.Projector, "__init__", spy)
    return built
