from scenerender.cli import main

main()
