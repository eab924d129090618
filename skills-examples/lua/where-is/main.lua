-- "Where did I put my ...": remembers where the user put things, in the skill's own
-- storage (no other skill can read it), and tells them again later.
--   "I put my keys in the kitchen drawer"  -> "OK, your keys are in the kitchen drawer."
--   "Where are my keys?"                   -> "Your keys are in the kitchen drawer."
-- Shows marvin.storage, the request's utterance, and a module of the skill (require).

local words = require("words")

local INDEX = "items"  -- "keys\nglasses\n...": what we know about, for "what do you remember"

local function known_items()
  local items = {}
  for item in (marvin.storage.get(INDEX) or ""):gmatch("[^\n]+") do items[#items + 1] = item end
  return items
end

local function save_index(items)
  marvin.storage.set(INDEX, table.concat(items, "\n"))
end

marvin.on("remember", function(slots, request)
  local item = words.clean(slots.item)
  local place = words.clean(slots.place)
  if item == "" or place == "" then
    marvin.say("Tell me like this: I put my keys in the drawer.")
    return
  end
  -- The template's preposition ("in", "under", ...) is not a slot: read it from the
  -- sentence as heard.
  local preposition = words.preposition_before(request.utterance, place) or "at"
  local where = preposition .. " " .. place
  marvin.storage.set("item:" .. item, where)
  local items = known_items()
  local known = false
  for _, other in ipairs(items) do known = known or other == item end
  if not known then
    items[#items + 1] = item
    save_index(items)
  end
  marvin.say("OK, your " .. item .. " " .. words.is_are(item) .. " " .. where .. ".")
end)

marvin.on("recall", function(slots)
  local item = words.clean(slots.item)
  local where = marvin.storage.get("item:" .. item)
  if where then
    marvin.say("Your " .. item .. " " .. words.is_are(item) .. " " .. where .. ".")
  else
    marvin.say("I don't know where your " .. item .. " " .. words.is_are(item)
      .. ". Tell me next time you put " .. words.it_them(item) .. " away.")
  end
end)

marvin.on("forget", function(slots)
  local item = words.clean(slots.item)
  marvin.storage.remove("item:" .. item)
  local items = {}
  for _, other in ipairs(known_items()) do
    if other ~= item then items[#items + 1] = other end
  end
  save_index(items)
  marvin.say("Good. I forgot where your " .. item .. " " .. words.was_were(item) .. ".")
end)

marvin.on("list", function()
  local items = known_items()
  if #items == 0 then
    marvin.say("You haven't told me where anything is yet.")
    return
  end
  local parts = {}
  for i, item in ipairs(items) do
    parts[i] = "your " .. item .. " " .. words.is_are(item) .. " "
      .. (marvin.storage.get("item:" .. item) or "somewhere")
  end
  marvin.say("I remember that " .. table.concat(parts, "; ") .. ".")
end)
