"""The manual's pages written from the code: the reference of the description file
format (:mod:`.reference`, ``docs/description.md``) and of the command line
(:mod:`.cli_reference`, ``docs/cli.md``)."""
