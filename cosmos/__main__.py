from cosmos.cli import main

main()
