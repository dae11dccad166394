from marraztu.cli import main

raise SystemExit(main())
