"""The targets of ``earl-m2t gen``: one module per renderer that ``transforms/targets.toml``
names, each declaring ``RENDERER`` (:class:`earl_m2t.gen.target.Renderer`)."""
