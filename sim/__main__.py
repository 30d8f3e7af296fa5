from sim.node import main

main()
