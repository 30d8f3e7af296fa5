from turtlectl.sim.node import main

main()
