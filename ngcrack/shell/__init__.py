"""The user's shell: the `ngcrack` command, the interactive explorer, files written whole and
interrupts honoured in every stage, and the names of the optional extras.
"""
