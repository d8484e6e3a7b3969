from scenerender.cli import entry_point

entry_point()
