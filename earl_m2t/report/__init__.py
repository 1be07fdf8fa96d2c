"""``earl-m2t report``: a static HTML specification of a model, composed of what ``gen``
makes (diagrams, tables) and what ``check`` and ``verify`` find."""
