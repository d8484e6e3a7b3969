"""Tools that render and measure, above the run layer: ``bench.py`` (``scenerender bench``:
speed against error over a sweep of quality knobs), ``quality.py`` (a GPU frame's error
against the CPU reference, by region) and ``perturbation.py`` (the diff rule's perturbation
corpus, ``python -m scenerender.tools.perturbation``). They open GL contexts and use the
run layer's ``Renderer``; nothing below this layer imports them.
"""
