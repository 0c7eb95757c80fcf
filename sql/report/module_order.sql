-- Modules in the order the interface description declares them.
select module from module_positions
order by position
