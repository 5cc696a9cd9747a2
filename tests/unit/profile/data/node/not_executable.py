# A program without the right to run it: the profile tests' <command> must name it so.
