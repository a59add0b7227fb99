
b = particle_arrays['fluid']
b.scalar = 'vmag'
